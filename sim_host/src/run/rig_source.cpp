#include "stickslip/host/run/rig_source.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>
#include <vector>

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

std::vector<SampledSignal> read_channel(const std::string& path, const RecordingOptions& options,
                                        RecordingReport& report) {
  LoadedRecording loaded = read_recording(path, options);
  report = loaded.report;
  return std::move(loaded.segments);
}

// Every channel comes from the same file with the same time base, so a text file gives equal
// grids (and equal gaps); a CAN log whose signals sit in different messages may not, and the fit
// compares sample n with sample n: such channels are refused, never shifted or trimmed.
void check_aligned(const std::string& path, const std::vector<SampledSignal>& a_u,
                   const std::vector<SampledSignal>& other, const char* name) {
  if (other.size() != a_u.size()) {
    throw HostError(fmt::format(
        "{}: {} has {} parts between gaps and a_u {}; the fit needs both on the same samples "
        "(put them in one message or one time column)",
        path, name, other.size(), a_u.size()));
  }
  for (std::size_t i = 0; i < a_u.size(); ++i) {
    const SampledSignal& u = a_u[i];
    const SampledSignal& o = other[i];
    if (o.t_s.size() != u.t_s.size() || std::fabs(o.t_s.front() - u.t_s.front()) > 0.5 * u.dt_s ||
        std::fabs(o.dt_s - u.dt_s) > kJitterTolerance * u.dt_s) {
      throw HostError(fmt::format(
          "{}: {} does not line up with a_u: {} samples from t = {} s every {:.6g} s against "
          "a_u's {} from t = {} s every {:.6g} s; the fit needs both on the same samples (put "
          "them in one message or one time column)",
          path, name, o.t_s.size(), o.t_s.front(), o.dt_s, u.t_s.size(), u.t_s.front(), u.dt_s));
    }
  }
}

// The parts end to end; their steps must agree (each part's own when no --dt is given).
void lay_end_to_end(const std::string& path, const std::vector<SampledSignal>& u,
                    const std::vector<SampledSignal>& x, RigRecording& rig) {
  rig.dt_s = u.front().dt_s;
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (std::fabs(u[i].dt_s - rig.dt_s) > kJitterTolerance * rig.dt_s) {
      throw HostError(fmt::format(
          "{}: the part from t = {} s has a step of {:.6g} s, the first part {:.6g} s; give --dt "
          "S to put both on the model's step",
          path, u[i].t_s.front(), u[i].dt_s, rig.dt_s));
    }
    if (u.size() > 1) rig.segment_starts.push_back(rig.t_s.size());
    rig.t_s.insert(rig.t_s.end(), u[i].t_s.begin(), u[i].t_s.end());
    rig.a_u_m_per_s2.insert(rig.a_u_m_per_s2.end(), u[i].a_u_m_per_s2.begin(),
                            u[i].a_u_m_per_s2.end());
    rig.a_x_m_per_s2.insert(rig.a_x_m_per_s2.end(), x[i].a_u_m_per_s2.begin(),
                            x[i].a_u_m_per_s2.end());
  }
}

}  // namespace

bool RigSourceOptions::defaults() const noexcept {
  return recording.defaults() && ax_signal.empty() && ax_unit.empty() && travel_signal.empty() &&
         travel_unit.empty();
}

RigSource read_rig_source(const std::string& path, const RigSourceOptions& options) {
  RigSource source;
  // The project's rig CSV (a column t) is read strictly, in SI units; a logger's export (its own
  // time column, units in the header, a banner, decimal commas) as simulate reads it.
  if (options.defaults() &&
      (has_mat_extension(path) || has_column(read_delimited_text(path), "t"))) {
    source.rig = read_rig_recording(path);
    return source;
  }
  if (has_mat_extension(path)) {
    throw HostError(path +
                    ": fit reads rig recordings from text or CAN logs; a .mat is read for a_u "
                    "only");
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
  const std::vector<SampledSignal> u = read_channel(path, options.recording, source.a_u);
  const std::vector<SampledSignal> x = read_channel(path, a_x, source.a_x);
  check_aligned(path, u, x, "a_x");
  RigRecording& rig = source.rig;
  rig.path = path;
  if (!x_r.signal.empty()) {
    const std::vector<SampledSignal> travel = read_channel(path, x_r, source.x_r);
    check_aligned(path, u, travel, "x_r");
    for (const SampledSignal& part : travel)
      rig.x_r_m.insert(rig.x_r_m.end(), part.a_u_m_per_s2.begin(), part.a_u_m_per_s2.end());
  }
  lay_end_to_end(path, u, x, rig);
  if (rig.t_s.size() < kMinimumSamples) {
    throw HostError(fmt::format("{}: {} samples; the fit needs at least {}", path, rig.t_s.size(),
                                kMinimumSamples));
  }
  return source;
}

}  // namespace stickslip::host
