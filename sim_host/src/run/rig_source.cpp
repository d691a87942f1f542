#include "stickslip/host/run/rig_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/delimited_text.hpp"

namespace stickslip::host {
namespace {

constexpr std::size_t kMinimumSamples = 16;  // as read_rig_recording()

bool has_mat_extension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  for (char& c : tail) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c + 32 : c);
  return tail == ".mat";
}

bool has_column(const DelimitedTable& table, const std::string& name) {
  for (const TextChannel& channel : table.channels)
    if (channel.name == name) return true;
  return false;
}

SampledSignal read_channel(const std::string& path, const RecordingOptions& options,
                           RecordingReport& report) {
  LoadedRecording loaded = read_recording(path, options);
  report = loaded.report;
  return std::move(loaded.segments.front());
}

// Every channel comes from the same file with the same time base, so a text file gives equal
// grids; a CAN log whose signals sit in different messages may not, and the fit compares sample
// n with sample n: such channels are refused, never shifted or trimmed.
void check_aligned(const std::string& path, const SampledSignal& a_u, const SampledSignal& other,
                   const char* name) {
  const double half_step = 0.5 * a_u.dt_s;
  if (other.t_s.size() != a_u.t_s.size() ||
      std::fabs(other.t_s.front() - a_u.t_s.front()) > half_step ||
      std::fabs(other.dt_s - a_u.dt_s) > kJitterTolerance * a_u.dt_s) {
    throw HostError(fmt::format(
        "{}: {} does not line up with a_u: {} samples from t = {} s every {:.6g} s against a_u's "
        "{} from t = {} s every {:.6g} s; the fit needs both on the same samples (put them in "
        "one message or one time column)",
        path, name, other.t_s.size(), other.t_s.front(), other.dt_s, a_u.t_s.size(),
        a_u.t_s.front(), a_u.dt_s));
  }
}

}  // namespace

bool RigSourceOptions::defaults() const noexcept {
  return recording.defaults() && ax_signal.empty() && ax_unit.empty() && travel_signal.empty() &&
         travel_unit.empty();
}

RigSource read_rig_source(const std::string& path, const RigSourceOptions& options) {
  RigSource source;
  if (options.defaults()) {
    source.rig = read_rig_recording(path);
    return source;
  }
  if (has_mat_extension(path)) {
    throw HostError(path +
                    ": fit reads rig recordings from text or CAN logs; a .mat is read for a_u "
                    "only");
  }
  if (options.recording.gaps == GapPolicy::split) {
    throw UsageError(
        "--gaps split: fit needs one continuous recording; use --gaps hold (gaps held) or cut "
        "the file at its gaps");
  }
  const bool can_log = !options.recording.dbc.empty();
  RecordingOptions a_x = options.recording;
  a_x.signal = options.ax_signal;
  a_x.unit = options.ax_unit;
  RecordingOptions x_r = options.recording;
  x_r.signal = options.travel_signal;
  x_r.unit = options.travel_unit;
  x_r.quantity = Quantity::length;
  if (can_log && a_x.signal.empty()) {
    throw UsageError("--dbc: give --ax-signal MESSAGE.SIGNAL for the seat acceleration a_x too");
  }
  if (!can_log && (a_x.signal.empty() || x_r.signal.empty())) {
    const DelimitedTable table = read_delimited_text(path);
    if (a_x.signal.empty()) {
      if (!has_column(table, "a_x")) {
        throw HostError(
            path +
            ": no column 'a_x' (the seat acceleration, m/s^2, which the fit compares the model "
            "with); give --ax-signal NAME");
      }
      a_x.signal = "a_x";
    }
    if (x_r.signal.empty() && has_column(table, "x_r")) x_r.signal = "x_r";
  }
  if (x_r.signal.empty() && !options.travel_unit.empty())
    throw UsageError("--travel-unit: give --travel-signal too");
  const SampledSignal u = read_channel(path, options.recording, source.a_u);
  const SampledSignal x = read_channel(path, a_x, source.a_x);
  check_aligned(path, u, x, "a_x");
  RigRecording& rig = source.rig;
  rig.path = path;
  if (!x_r.signal.empty()) {
    SampledSignal travel = read_channel(path, x_r, source.x_r);
    check_aligned(path, u, travel, "x_r");
    rig.x_r_m = std::move(travel.a_u_m_per_s2);
  }
  if (u.t_s.size() < kMinimumSamples) {
    throw HostError(fmt::format("{}: {} samples; the fit needs at least {}", path, u.t_s.size(),
                                kMinimumSamples));
  }
  rig.t_s = u.t_s;
  rig.dt_s = u.dt_s;
  rig.a_u_m_per_s2 = u.a_u_m_per_s2;
  rig.a_x_m_per_s2 = x.a_u_m_per_s2;
  return source;
}

}  // namespace stickslip::host
