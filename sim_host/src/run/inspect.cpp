#include "stickslip/host/run/inspect.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

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

// A path or name as one shell word.
std::string shell_word(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789._/+-=:,@") == std::string::npos) {
    return word;
  }
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct Timing {
  std::string text;
  double median_s = 0;
  bool uniform = true;
  std::size_t gaps = 0;
};

// `origin_s`: the clock's reading at t = 0 (RawSeries::time_origin_s).
Timing describe_times(const std::vector<double>& t, double origin_s = 0.0) {
  Timing timing;
  if (t.size() < 2) {
    timing.text = fmt::format("{} sample(s): too few to run\n", t.size());
    return timing;
  }
  double low = t[1] - t[0], high = low;
  for (std::size_t i = 1; i < t.size(); ++i) {
    low = std::min(low, t[i] - t[i - 1]);
    high = std::max(high, t[i] - t[i - 1]);
  }
  const double median = median_step(t);
  timing.median_s = nominal_step(t);
  const double h = timing.median_s;
  double jitter = 0.0, first_gap_t = 0.0, first_gap_s = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double step = t[i] - t[i - 1];
    if (step > kGapSteps * h) {
      if (timing.gaps++ == 0) first_gap_t = t[i - 1], first_gap_s = step;
    } else {
      jitter = std::max(jitter, std::fabs(step - h) / h);
    }
  }
  timing.uniform = steps_uniform(jitter, h, origin_s + t.front(), origin_s + t.back());
  timing.text = fmt::format(
      "  samples {}, from t = {} s to {} s ({:.6g} s)\n  rate {:.6g} Hz (the mean step); step "
      "min/median/max {:.6g} / {:.6g} / {:.6g} s; jitter {:.3g} % of the mean step ({})\n",
      t.size(), t.front(), t.back(), t.back() - t.front(), 1.0 / h, low, median, high,
      100.0 * jitter, timing.uniform ? "uniform" : "to be put on a grid");
  timing.text += timing.gaps == 0
                     ? "  gaps: none (a gap is a step over 1.5 median steps)\n"
                     : fmt::format("  gaps: {} (the first after t = {} s, {} s long)\n",
                                   timing.gaps, first_gap_t, first_gap_s);
  return timing;
}

std::string describe_values(const std::string& label, const std::string& unit,
                            const std::vector<double>& v) {
  std::size_t nans = 0;
  double low = std::numeric_limits<double>::infinity(), high = -low, sum2 = 0.0;
  for (double x : v) {
    if (std::isnan(x)) {
      ++nans;
      continue;
    }
    low = std::min(low, x), high = std::max(high, x), sum2 += x * x;
  }
  double factor = 0.0;
  const bool acceleration = acceleration_unit_factor(unit, factor);
  return fmt::format(
      "  {} [{}]{}: min {:.6g}, max {:.6g}, rms {:.6g}; NaN {}; at full scale {} samples "
      "(runs of >= 3 at the min or max that the signal ran into)\n",
      label, unit.empty() ? "no unit" : unit, acceleration ? "" : " (not an acceleration)", low,
      high, std::sqrt(sum2 / static_cast<double>(v.size())), nans, clipped_samples(v));
}

// "--dt 0.001 --gaps hold" as the times need.
std::string timing_flags(const Timing& timing) {
  std::string flags;
  if (!timing.uniform ||
      std::fabs(timing.median_s - kSuggestedDtS) > kJitterTolerance * kSuggestedDtS)
    flags += fmt::format(" --dt {}", kSuggestedDtS);
  if (timing.gaps > 0) flags += " --gaps hold";
  return flags;
}

std::string suggestion(const std::string& path, const std::string& flags) {
  std::string stem = path.substr(0, path.find_last_of('.'));
  if (stem.empty() || path.find_last_of('.') < path.find_last_of('/') + 1) stem = path;
  return fmt::format(
      "simulate it with (add your seat and friction: --mass, --stiffness, --damping, --ffk):\n"
      "stickslip simulate --input {}{} --model stick-slip --output {}\n",
      shell_word(path), flags, shell_word(stem + ".trace.csv"));
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

// The number right before "Hz" at `hz` (blanks between allowed): digits, with at most one '.' or
// ',' between digits; empty when there is none. A scan rather than std::regex, whose GCC 12
// headers trip -Wmaybe-uninitialized in the sanitizer build.
std::string number_before(const std::string& line, std::size_t hz) {
  std::size_t end = hz;
  while (end > 0 && std::isspace(static_cast<unsigned char>(line[end - 1]))) --end;
  std::size_t begin = end;
  while (begin > 0 && is_digit(line[begin - 1])) --begin;
  if (begin == end) return std::string();
  if (begin >= 2 && (line[begin - 1] == '.' || line[begin - 1] == ',') &&
      is_digit(line[begin - 2])) {
    --begin;
    while (begin > 0 && is_digit(line[begin - 1])) --begin;
  }
  return line.substr(begin, end - begin);
}

// "Sample rate: 512 Hz" in a logger's banner (the first number followed by Hz, any case).
std::optional<double> banner_rate(const std::string& path, std::size_t lines_above) {
  std::ifstream file(path);
  std::string line;
  for (std::size_t n = 0; n < lines_above && std::getline(file, line); ++n) {
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      if (std::tolower(static_cast<unsigned char>(line[i])) != 'h' ||
          std::tolower(static_cast<unsigned char>(line[i + 1])) != 'z')
        continue;
      std::string number = number_before(line, i);
      if (number.empty()) continue;
      std::replace(number.begin(), number.end(), ',', '.');
      return std::stod(number);
    }
  }
  return std::nullopt;
}

std::string inspect_text(const std::string& path, const RecordingOptions& options) {
  const DelimitedTable table = read_delimited_text(path);
  std::string text = fmt::format(
      "{}: delimited text, separator {}, decimal mark '{}', {} columns, header {}, data from "
      "line {}\n",
      path,
      table.separator == '\t'  ? "tab"
      : table.separator == ' ' ? "blanks"
                               : fmt::format("'{}'", table.separator),
      table.decimal_mark, table.channels.size(),
      table.header_line ? fmt::format("at line {}", table.header_line) : std::string("none"),
      table.first_data_line);
  const TextChannel* time = text_time_column(path, table, options);
  std::string flags;
  std::vector<double> t;
  if (options.rate_hz > 0 || time == nullptr) {
    std::optional<double> rate;
    if (options.rate_hz > 0) rate = options.rate_hz;
    if (!rate) rate = banner_rate(path, table.first_data_line - 1);
    if (!rate) {
      text += "time: no time column and no rate in the banner: give --rate HZ\n";
      flags += " --rate HZ";
    } else {
      text += fmt::format("time: no time column; {} Hz as {}\n", *rate,
                          options.rate_hz > 0 ? "given" : "the banner states");
      flags += fmt::format(" --rate {}", *rate);
      for (std::size_t i = 0; i < table.channels.front().values.size(); ++i)
        t.push_back(static_cast<double>(i) / *rate);
    }
    time = nullptr;
  } else {
    text += fmt::format("time: column {}\n", time->name);
    if (!options.time.empty()) flags += " --time " + shell_word(time->name);
    t = time->values;
    if (time->unit == "ms")
      for (double& x : t) x *= 1e-3;
  }
  Timing timing;
  if (!t.empty()) {
    timing = describe_times(t);
    text += timing.text;
  }
  text += "channels:\n";
  const TextChannel* pick = nullptr;
  for (std::size_t i = 0; i < table.channels.size(); ++i) {
    const TextChannel& c = table.channels[i];
    if (&c == time) continue;
    text += describe_values(fmt::format("{} {}", i + 1, c.name), c.unit, c.values);
    double factor = 0.0;
    const bool acceleration = !c.unit.empty() && acceleration_unit_factor(c.unit, factor);
    if (pick == nullptr && (acceleration || c.name == "a_u")) pick = &c;
  }
  if (!options.signal.empty()) pick = &table.channel(options.signal);
  if (pick == nullptr) {
    for (const TextChannel& c : table.channels)
      if (&c != time && pick == nullptr) pick = &c;
    text += "(no column has an acceleration unit: the suggestion reads the first as m/s^2)\n";
  }
  if (pick->name != "a_u") flags = " --signal " + shell_word(pick->name) + flags;
  double factor = 0.0;
  if (!pick->unit.empty() && !acceleration_unit_factor(pick->unit, factor))
    flags += " --unit m/s^2";
  if (!t.empty()) flags += timing_flags(timing);
  return text + suggestion(path, flags);
}

// "  CabFloor.AccZ: 12 frames of the message too short for the signal (not decoded)\n" or "".
std::string describe_too_short(const std::string& name, std::size_t frames_too_short) {
  if (frames_too_short == 0) return "";
  return fmt::format("  {}: {} frames of the message too short for the signal (not decoded)\n",
                     name, frames_too_short);
}

std::string inspect_can(const std::string& path, const RecordingOptions& options) {
  const CanLog log = read_can_log(path);
  std::string text = fmt::format("{}: {} CAN log, {} data frames, {} other events skipped\n", path,
                                 format_name(log.format), log.frames.size(), log.skipped_events);
  const std::vector<std::string> channels = log_channels(log);
  std::map<std::string, std::size_t> frames_on;
  for (const LogFrame& frame : log.frames) ++frames_on[frame.channel];
  require_channel(log, path, options.channel);
  text += "channels:";
  for (std::size_t i = 0; i < channels.size(); ++i) {
    text += fmt::format("{} {} ({} frames)", i == 0 ? "" : ",",
                        channels[i].empty() ? "(none)" : channels[i], frames_on[channels[i]]);
  }
  text += channels.size() > 1 ? " (pick one with --channel NAME)\n" : "\n";
  // Per bus: the same id on two channels is two messages.
  std::map<std::tuple<std::uint32_t, bool, std::string>, std::vector<double>> by_id;
  for (const LogFrame& frame : log.frames) {
    if (!options.channel.empty() && frame.channel != options.channel) continue;
    by_id[{frame.id, frame.extended, frame.channel}].push_back(frame.time_s);
  }
  const bool several = channels.size() > 1 && options.channel.empty();
  if (options.dbc.empty()) {
    text += "ids (give --dbc FILE to decode their signals):\n";
    for (const auto& [id, times] : by_id) {
      text += fmt::format("  {}{:X}{}: {} frames, {:.6g} Hz\n",
                          several ? std::get<2>(id) + " " : std::string(), std::get<0>(id),
                          std::get<1>(id) ? "x" : "", times.size(),
                          times.size() > 1 ? 1.0 / nominal_step(times) : 0.0);
    }
    return text + "simulate it with: stickslip simulate --input " + shell_word(path) +
           " --dbc DBC --signal MESSAGE.SIGNAL --dt 0.001 --model stick-slip --output OUT.csv\n";
  }
  const Dbc dbc = read_dbc(options.dbc);
  text += fmt::format("signals of {} in the log:\n", options.dbc);
  std::string pick = options.signal;
  std::string pick_channel = options.channel;
  std::vector<double> pick_times;
  for (const DbcMessage& message : dbc.messages) {
    // The channels that carry the message, each described apart.
    std::vector<std::string> carrying;
    for (const auto& [id, times] : by_id) {
      if (std::get<0>(id) == message.id && std::get<1>(id) == message.extended)
        carrying.push_back(std::get<2>(id));
    }
    for (const std::string& channel : carrying) {
      const std::string on = options.channel.empty() && carrying.size() > 1 ? channel : "";
      for (const DbcSignal& signal : message.signals) {
        const std::string name = message.name + "." + signal.name;
        const std::string label = on.empty() ? name : name + " on " + on;
        SignalSeries series;
        try {
          series = extract_signal(log, path, dbc, name, on.empty() ? options.channel : on);
        } catch (const UsageError&) {
          throw;
        } catch (const HostError& error) {
          // A signal no frame is long enough for is described, not the end of the inspection.
          text += fmt::format("  {}: not decoded: {}\n", label, error.what());
          continue;
        }
        text += describe_values(label, series.unit, series.values);
        text += describe_too_short(label, series.frames_too_short);
        double factor = 0.0;
        if (pick.empty() && !series.unit.empty() && acceleration_unit_factor(series.unit, factor))
          pick = name;
        if (name == pick && pick_times.empty()) {
          pick_times = series.t_s;
          if (!on.empty()) pick_channel = on;
        }
      }
    }
  }
  if (pick.empty()) {
    return text + "no signal of the DBC in the log has an acceleration unit; give --signal\n";
  }
  if (pick_times.empty()) pick_times = extract_signal(log, path, dbc, pick, options.channel).t_s;
  const std::string flags_channel =
      pick_channel.empty() ? std::string() : " --channel " + shell_word(pick_channel);
  text += fmt::format("time of {}{}:\n", pick, pick_channel.empty() ? "" : " on " + pick_channel);
  const Timing timing = describe_times(pick_times, log.start_time_epoch_s);
  text += timing.text;
  return text + suggestion(path, " --dbc " + shell_word(options.dbc) + flags_channel +
                                     " --signal " + shell_word(pick) + timing_flags(timing));
}

std::string inspect_mat(const std::string& path) {
  const SampledSignal signal = read_signal_mat(path, MatTimes::increasing);
  std::string text = fmt::format("{}: MATLAB file, variables t (or dt) and a_u\n", path);
  const Timing timing = describe_times(signal.t_s);
  text += timing.text + "channels:\n" + describe_values("a_u", "m/s^2", signal.a_u_m_per_s2);
  return text + suggestion(path, timing_flags(timing));
}

}  // namespace

std::string inspect_recording(const std::string& path, const RecordingOptions& options) {
  const std::string extension = lower(path.substr(path.find_last_of('.') + 1));
  // Only a CAN log has buses: on another file --channel would be read over unnoticed, so it is
  // refused there, naming the option.
  if (!options.channel.empty() && extension == "mat") {
    throw UsageError("--channel " + options.channel + ": " + path +
                     " is a .mat recording; only a CAN log has channels");
  }
  if (extension == "mat") return inspect_mat(path);
  if (!options.channel.empty()) {
    try {
      (void)detect_can_log_format(path);
    } catch (const HostError& error) {
      throw HostError("--channel " + options.channel + ": " + error.what());
    }
  }
  if (!options.dbc.empty() || !options.channel.empty()) return inspect_can(path, options);
  try {
    return inspect_text(path, options);
  } catch (const HostError&) {
    std::optional<CanLogFormat> format;
    try {
      format = detect_can_log_format(path);
    } catch (const HostError&) {
    }
    if (format && extension != "csv" && extension != "txt") return inspect_can(path, options);
    throw;
  }
}

}  // namespace stickslip::host
