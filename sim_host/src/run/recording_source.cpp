#include "stickslip/host/run/recording_source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>

#include "recording_series.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"
#include "stickslip/host/io/can_signal.hpp"
#include "stickslip/host/io/dbc.hpp"
#include "stickslip/host/io/delimited_text.hpp"
#include "stickslip/host/io/mat_file.hpp"

namespace stickslip::host {
namespace {

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool has_mat_extension(const std::string& path) {
  return path.size() >= 4 && lower(path.substr(path.size() - 4)) == ".mat";
}

// The project's own CSV: a first line naming t or a_u (without a byte order mark, which that
// reader does not strip), read by read_signal_csv as always, its errors included; so is a file
// that reader cannot open, so that its message stays the one users know.
bool is_project_csv(const std::string& path) {
  try {
    CsvReader reader(path);
    const auto& columns = reader.columns();
    if (!columns.empty() && columns.front().rfind("\xEF\xBB\xBF", 0) == 0) return false;
    return std::find(columns.begin(), columns.end(), "t") != columns.end() ||
           std::find(columns.begin(), columns.end(), "a_u") != columns.end();
  } catch (const HostError&) {
    return true;
  }
}

std::string column_list(const DelimitedTable& table) {
  std::string list;
  for (const TextChannel& channel : table.channels) {
    if (!list.empty()) list += ", ";
    list += channel.unit.empty() ? channel.name : channel.name + " [" + channel.unit + "]";
  }
  return list;
}

RawSeries read_text_series(const std::string& path, const RecordingOptions& options) {
  const DelimitedTable table = read_delimited_text(path);
  RawSeries raw;
  const TextChannel* time = text_time_column(path, table, options);
  if (time == nullptr && !(options.rate_hz > 0)) {
    throw HostError(fmt::format("{}: no time column (columns: {}); give --time NAME or --rate HZ",
                                path, column_list(table)));
  }
  const TextChannel* signal = nullptr;
  if (!options.signal.empty()) {
    signal = &table.channel(options.signal);
  } else {
    for (const TextChannel& channel : table.channels)
      if (channel.name == "a_u") signal = &channel;
  }
  if (signal == nullptr) {
    throw HostError(
        fmt::format("{}: which column is the acceleration? give --signal NAME or "
                    "INDEX (columns: {}; stickslip inspect {} suggests the flags)",
                    path, column_list(table), path));
  }
  if (signal == time) {
    throw UsageError(fmt::format("--signal {}: that is the time column of {}", signal->name, path));
  }
  raw.values = signal->values;
  raw.lines = table.row_lines;
  // The actuator force column, by its exact name as the t,a_u CSV reader takes it (csv_reader.hpp).
  for (const TextChannel& channel : table.channels) {
    if (channel.name != "f_a" || &channel == signal || &channel == time) continue;
    if (!channel.unit.empty() && channel.unit != "N") {
      throw HostError(fmt::format("{}: column 'f_a' (the actuator force) is in '{}'; N expected",
                                  path, channel.unit));
    }
    raw.f_a_n = channel.values;
  }
  raw.unit = options.unit.empty() ? signal->unit : options.unit;
  raw.source = fmt::format("text column {}", signal->name);
  if (time == nullptr) {
    raw.from_rate = true;
    raw.t_s.resize(raw.values.size());
    for (std::size_t i = 0; i < raw.t_s.size(); ++i)
      raw.t_s[i] = static_cast<double>(i) / options.rate_hz;
    return raw;
  }
  double scale = 1.0;
  if (time->unit == "ms") {
    scale = 1e-3;
  } else if (!time->unit.empty() && time->unit != "s") {
    throw HostError(fmt::format("{}: time column {} has unit '{}'; s or ms expected", path,
                                time->name, time->unit));
  }
  raw.t_s = time->values;
  if (scale != 1.0)
    for (double& t : raw.t_s) t *= scale;
  return raw;
}

RawSeries read_can_series(const std::string& path, const RecordingOptions& options) {
  if (options.signal.empty()) {
    throw UsageError("--dbc: give --signal MESSAGE.SIGNAL too (stickslip inspect " + path +
                     " --dbc " + options.dbc + " lists them)");
  }
  if (!options.time.empty() || options.rate_hz > 0) {
    throw UsageError("--time/--rate: a CAN log carries its own timestamps");
  }
  const Dbc dbc = read_dbc(options.dbc);
  const CanLog log = read_can_log(path);
  SignalSeries series = extract_signal(log, path, dbc, options.signal, options.channel);
  RawSeries raw;
  raw.t_s = std::move(series.t_s);
  raw.values = std::move(series.values);
  raw.unit = options.unit.empty() ? series.unit : options.unit;
  raw.frames_too_short = series.frames_too_short;
  raw.frames = std::move(series.frames);
  raw.frame_lines = series.frame_lines;
  raw.time_origin_s = log.start_time_epoch_s;
  raw.source = fmt::format("{} {}", format_name(log.format), series.name);
  return raw;
}

// A file the text reader refused that is a CAN log by its content (not by a .csv or .txt name):
// the message says what reading it needs; otherwise the text reader's message stands.
[[noreturn]] void rethrow_for_can_log(const std::string& path) {
  std::optional<CanLogFormat> format;
  try {
    format = detect_can_log_format(path);
  } catch (const HostError&) {
  }
  const std::string extension = lower(path.substr(path.find_last_of('.') + 1));
  if (format && extension != "csv" && extension != "txt") {
    throw HostError(fmt::format("{}: a {} CAN log; give --dbc FILE and --signal MESSAGE.SIGNAL",
                                path, format_name(*format)));
  }
  throw;
}

}  // namespace

const TextChannel* text_time_column(const std::string& path, const DelimitedTable& table,
                                    const RecordingOptions& options) {
  if (!options.time.empty()) return &table.channel(options.time);
  // A column named t or time first, wherever it stands; else the first in s or ms.
  std::vector<const TextChannel*> candidates;
  for (const TextChannel& channel : table.channels) {
    const std::string name = lower(channel.name);
    if (name == "t" || name == "time") candidates.push_back(&channel);
  }
  for (const TextChannel& channel : table.channels) {
    if (channel.unit == "s" || channel.unit == "ms") candidates.push_back(&channel);
  }
  for (const TextChannel* found : candidates) {
    const TextChannel& channel = *found;
    if (options.rate_hz > 0) {
      throw UsageError(fmt::format(
          "--rate {}: {} has a time column, {}; --rate is for text without one (drop it, or "
          "choose the column with --time NAME)",
          options.rate_hz, path,
          channel.unit.empty() ? channel.name : channel.name + " [" + channel.unit + "]"));
    }
    return &channel;
  }
  return nullptr;
}

bool RecordingOptions::defaults() const noexcept {
  return signal.empty() && dbc.empty() && channel.empty() && time.empty() && !(rate_hz > 0) &&
         unit.empty() && gaps == GapPolicy::refuse && !(dt_s > 0);
}

bool RecordingReport::acted() const noexcept {
  return regridded_samples > 0 || resampled || gaps > 0 || held_samples > 0 ||
         clipped_samples > 0 || segments > 1 || frames_too_short > 0 || short_segment_samples > 0;
}

RawSeries read_raw_series(const std::string& path, const RecordingOptions& options) {
  if (!options.dbc.empty()) return read_can_series(path, options);
  try {
    return read_text_series(path, options);
  } catch (const UsageError&) {
    throw;
  } catch (const HostError&) {
    rethrow_for_can_log(path);
  }
}

LoadedRecording read_recording(const std::string& path, const RecordingOptions& options) {
  if (options.rate_hz > 0 && !options.time.empty())
    throw UsageError("--time and --rate: give one of them");
  if (!options.channel.empty() && options.dbc.empty()) {
    throw UsageError("--channel " + options.channel +
                     ": picks the bus of a CAN log read with --dbc; give --dbc FILE too");
  }
  if (!options.unit.empty()) {
    double factor = 0;
    if (!unit_factor(options.quantity, options.unit, factor)) {
      throw UsageError(options.quantity == Quantity::length
                           ? "travel unit: '" + options.unit + "' is not m, mm, cm or um"
                           : "--unit: '" + options.unit + "' is not g, m/s^2 or mm/s^2");
    }
  }
  LoadedRecording loaded;
  RawSeries raw;
  if (has_mat_extension(path)) {
    if (!options.signal.empty() || !options.dbc.empty() || !options.time.empty() ||
        options.rate_hz > 0) {
      throw UsageError(path +
                       ": a .mat recording holds t (or dt) and a_u; --signal, --dbc, "
                       "--time and --rate are for text and CAN logs");
    }
    SampledSignal signal =
        read_signal_mat(path, options.defaults() ? MatTimes::uniform : MatTimes::increasing);
    if (options.defaults()) {
      loaded.report.source = ".mat a_u";
      loaded.report.samples_read = signal.t_s.size();
      loaded.report.source_rate_hz = 1.0 / signal.dt_s;
      loaded.segments.push_back(std::move(signal));
      return loaded;
    }
    raw.t_s = std::move(signal.t_s);
    raw.values = std::move(signal.a_u_m_per_s2);
    raw.unit = options.unit;
    raw.source = ".mat a_u";
  } else if (options.defaults() && is_project_csv(path)) {
    SampledSignal signal = read_signal_csv(path);
    loaded.report.source = "t,a_u CSV";
    loaded.report.samples_read = signal.t_s.size();
    loaded.report.source_rate_hz = 1.0 / signal.dt_s;
    loaded.segments.push_back(std::move(signal));
    return loaded;
  } else {
    raw = read_raw_series(path, options);
  }
  loaded.segments = condition_series(path, std::move(raw), options, loaded.report);
  return loaded;
}

void require_force_as_read(const std::string& path, const LoadedRecording& recording) {
  const std::vector<double>& f_a_n = recording.segments.front().f_a_n;
  if (recording.report.actuator_force_unaligned) {
    throw UsageError(path +
                     ": column 'f_a': an actuator force runs on a recording read as it is (one "
                     "part, its own step: no gaps held or split, no regridding, no resampling)");
  }
  if (!f_a_n.empty() && (recording.segments.size() != 1 ||
                         f_a_n.size() != recording.segments.front().a_u_m_per_s2.size())) {
    throw UsageError(path +
                     ": column 'f_a': an actuator force runs on a recording read as it is (one "
                     "part, its own step: no --gaps split, no resampling)");
  }
}

void check_scene_rate(const std::string& path, const RecordingOptions& options, double dt_s,
                      const std::string& scene_path, double scene_dt_s) {
  if (options.dt_s > 0.0 || !(scene_dt_s > 0.0) ||
      std::fabs(dt_s - scene_dt_s) <= 1e-9 * scene_dt_s)
    return;
  throw HostError(fmt::format(
      "{}: dt = {} s, but the scene {} has sample_rate_hz = {} (dt = {} s); --dt {} resamples the "
      "recording to the scene's rate",
      path, dt_s, scene_path, 1.0 / scene_dt_s, scene_dt_s, scene_dt_s));
}

SampledSignal read_continuous_recording(const std::string& path, const RecordingOptions& options,
                                        const char* command, RecordingReport* report) {
  if (options.gaps == GapPolicy::split) {
    throw UsageError(std::string("--gaps split: ") + command +
                     " streams one continuous signal (a SeatInput frame per sample, which the node "
                     "steps through as one run); use --gaps hold, or simulate, which runs each "
                     "part alone");
  }
  LoadedRecording loaded = read_recording(path, options);
  if (report != nullptr) *report = loaded.report;
  return std::move(loaded.segments.front());
}

bool acceleration_unit_factor(const std::string& unit, double& factor) {
  const std::string u = lower(unit);
  if (u.empty() || u == "m/s^2" || u == "m/s2" || u == "m/s\xc2\xb2" || u == "m s^-2") {
    factor = 1.0;
  } else if (u == "g") {
    factor = 9.80665;  // standard gravity, exact by definition
  } else if (u == "mm/s^2" || u == "mm/s2" || u == "mm/s\xc2\xb2") {
    factor = 1e-3;
  } else {
    return false;
  }
  return true;
}

bool length_unit_factor(const std::string& unit, double& factor) {
  const std::string u = lower(unit);
  if (u.empty() || u == "m") {
    factor = 1.0;
  } else if (u == "mm") {
    factor = 1e-3;
  } else if (u == "cm") {
    factor = 1e-2;
  } else if (u == "um" || u == "\xc2\xb5m" || u == "\xce\xbcm") {
    factor = 1e-6;
  } else {
    return false;
  }
  return true;
}

bool unit_factor(Quantity quantity, const std::string& unit, double& factor) {
  return quantity == Quantity::length ? length_unit_factor(unit, factor)
                                      : acceleration_unit_factor(unit, factor);
}

bool steps_uniform(double jitter, double step_s, double t_first_s, double t_last_s) noexcept {
  const double largest = std::max(std::fabs(t_first_s), std::fabs(t_last_s));
  const double spacing = std::nextafter(largest, HUGE_VAL) - largest;
  return jitter <= kJitterTolerance || jitter * step_s <= 2.0 * spacing;
}

bool parse_gap_policy(const std::string& text, GapPolicy& policy) {
  if (text == "refuse")
    policy = GapPolicy::refuse;
  else if (text == "hold")
    policy = GapPolicy::hold;
  else if (text == "split")
    policy = GapPolicy::split;
  else
    return false;
  return true;
}

}  // namespace stickslip::host
