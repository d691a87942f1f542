// The time side of reading a recording: order, gaps, jitter, unit, and the model's step.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "recording_series.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/signals/resample.hpp"

namespace stickslip::host {
namespace {

// "FILE:LINE: " for text and text CAN logs, "FILE: data frame N: " for BLF, "FILE: sample N: "
// otherwise (.mat).
std::string where(const std::string& path, const RawSeries& raw, std::size_t i) {
  if (i < raw.lines.size()) return fmt::format("{}:{}: ", path, raw.lines[i]);
  if (i < raw.frames.size()) {
    if (raw.frame_lines) return fmt::format("{}:{}: ", path, raw.frames[i]);
    return fmt::format("{}: data frame {}: ", path, raw.frames[i]);
  }
  return fmt::format("{}: sample {}: ", path, i + 1);
}

void check_times(const std::string& path, const RawSeries& raw) {
  if (raw.t_s.size() < 2) {
    throw HostError(fmt::format("{}: {} sample{}; at least 2 are needed", path, raw.t_s.size(),
                                raw.t_s.size() == 1 ? "" : "s"));
  }
  for (std::size_t i = 0; i < raw.t_s.size(); ++i) {
    if (!std::isfinite(raw.values[i]) || !(std::fabs(raw.t_s[i]) <= 1e15)) {
      throw HostError(fmt::format("{}t = {} s, value {}: not a finite number within the time range",
                                  where(path, raw, i), raw.t_s[i], raw.values[i]));
    }
    if (i > 0 && !(raw.t_s[i] > raw.t_s[i - 1])) {
      throw HostError(fmt::format("{}t = {} s does not come after {} s", where(path, raw, i),
                                  raw.t_s[i], raw.t_s[i - 1]));
    }
  }
}

struct Part {
  std::vector<double> t_s, values;
};

// Cuts at the gaps (split), fills them with the value before (hold), or keeps one part.
std::vector<Part> parts_at_gaps(RawSeries& raw, double step, const RecordingOptions& options,
                                RecordingReport& report) {
  std::vector<Part> parts(1);
  for (std::size_t i = 0; i < raw.t_s.size(); ++i) {
    const double gap = i > 0 ? raw.t_s[i] - raw.t_s[i - 1] : 0.0;
    if (gap > kGapSteps * step) {
      if (options.gaps == GapPolicy::split) {
        parts.emplace_back();
      } else {  // hold: the missing samples of the nominal rate repeat the last one
        const auto missing = static_cast<std::size_t>(std::llround(gap / step)) - 1;
        for (std::size_t k = 1; k <= missing; ++k) {
          parts.back().t_s.push_back(raw.t_s[i - 1] + static_cast<double>(k) * step);
          parts.back().values.push_back(raw.values[i - 1]);
        }
        report.held_samples += missing;
      }
    }
    parts.back().t_s.push_back(raw.t_s[i]);
    parts.back().values.push_back(raw.values[i]);
  }
  return parts;
}

// 1e9 samples of 8 bytes, several arrays of them per run: beyond it the machine runs out first.
constexpr double kMaxResampledSamples = 1e9;

double part_jitter(const Part& part, double step) {
  double jitter = 0.0;
  for (std::size_t i = 1; i < part.t_s.size(); ++i)
    jitter = std::max(jitter, std::fabs(part.t_s[i] - part.t_s[i - 1] - step) / step);
  return jitter;
}

// One part on the model's step: uniform parts as they are, jittered ones through the spline onto
// the nominal grid, then libsoxr when the nominal rate is not the model's.
// `origin_s`: RawSeries::time_origin_s.
SampledSignal onto_model_step(const std::string& path, Part part, double step, double origin_s,
                              const RecordingOptions& options, RecordingReport& report) {
  const std::size_t n = part.t_s.size();
  SampledSignal signal;
  const double jitter = part_jitter(part, step);
  const bool uniform =
      steps_uniform(jitter, step, origin_s + part.t_s.front(), origin_s + part.t_s.back());
  if (!uniform && !(options.dt_s > 0)) {
    throw HostError(fmt::format(
        "{}: the sample times jitter by up to {:.3g} % of the {:.6g} s step; give --dt S to put "
        "them on the model's step",
        path, 100.0 * jitter, step));
  }
  double grid_step = (part.t_s.back() - part.t_s.front()) / static_cast<double>(n - 1);
  std::vector<double> values = std::move(part.values);
  // Grid counts get a millionth of a step of slack: with quantized times (candump) the span is a
  // whole number of steps only to rounding.
  if (!uniform) {
    grid_step = step;
    const auto count =
        static_cast<std::size_t>(std::floor((part.t_s.back() - part.t_s.front()) / step + 1e-6)) +
        1;
    values = spline_onto_grid(part.t_s, values, part.t_s.front(), step, count);
    report.regridded_samples += count;
  }
  const double t0 = part.t_s.front();
  bool resampled = false;
  if (options.dt_s > 0 && std::fabs(grid_step - options.dt_s) > kJitterTolerance * options.dt_s) {
    // Refused before a grid that would not fit in memory is allocated (a --dt given in ms).
    const double samples = (part.t_s.back() - part.t_s.front()) / options.dt_s + 1.0;
    if (!(samples <= kMaxResampledSamples)) {
      throw UsageError(fmt::format(
          "--dt {}: {:.3g} samples from the {:.6g} s of {}, more than the {:.0e} a recording may "
          "have (--dt is in seconds)",
          options.dt_s, samples, part.t_s.back() - part.t_s.front(), path, kMaxResampledSamples));
    }
    values = resample_step(values, grid_step, options.dt_s);
    resampled = report.resampled = true;
    report.resampled_to_hz = 1.0 / options.dt_s;
    grid_step = options.dt_s;
  } else if (options.dt_s > 0) {
    grid_step = options.dt_s;
  }
  signal.dt_s = grid_step;
  if (uniform && !resampled) {
    signal.t_s = std::move(part.t_s);  // echoed exactly
  } else {
    signal.t_s.resize(values.size());
    for (std::size_t k = 0; k < values.size(); ++k)
      signal.t_s[k] = t0 + static_cast<double>(k) * grid_step;
  }
  signal.a_u_m_per_s2 = std::move(values);
  return signal;
}

}  // namespace

double median_step(const std::vector<double>& t) {
  std::vector<double> steps(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) steps[i - 1] = t[i] - t[i - 1];
  const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  return *middle;
}

double nominal_step(const std::vector<double>& t) {
  const double median = median_step(t);
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double step = t[i] - t[i - 1];
    if (step <= kGapSteps * median) sum += step, ++count;
  }
  return sum / static_cast<double>(count);
}

namespace {

// Quanta (the signal's resolution) over which the slope into and out of a run is measured, and
// how far beyond the run's level that slope must carry by the run's middle for the run to be a
// cut-off peak. A smooth peak, quantized, dwells at its top level while it rises and falls less
// than a quantum: measured over two quanta, less one for rounding, its slope carries it at most
// about 2.7 quanta past the level; 4 leaves room for noise (in 3000 random quantized sums of
// sines with noise, none was taken for clipping; sines cut at 80 % of their peak were found
// unless a period had fewer than about 16 samples).
constexpr double kSlopeQuanta = 2.0;
constexpr double kClippedQuanta = 4.0;

// How far beyond `level` the signal's slope next to the run [begin, end) would have carried it
// by the run's middle, walking from the run in direction `side` (-1 before it, +1 after it)
// until the signal is kSlopeQuanta quanta from the level; < 0 when the run has no neighbour
// there.
double carried_past(const std::vector<double>& v, std::size_t begin, std::size_t end, int side,
                    double level, double quantum) {
  const std::size_t run = end - begin;
  if ((side < 0 && begin == 0) || (side > 0 && end == v.size())) return -1.0;
  std::size_t k = side < 0 ? begin - 1 : end;
  std::size_t steps = 0;
  double drop = 0.0;
  while (steps < run) {
    ++steps;
    drop = std::fabs(level - v[k]);
    if (drop >= kSlopeQuanta * quantum) break;
    if ((side < 0 && k == 0) || (side > 0 && k + 1 == v.size())) break;
    k = side < 0 ? k - 1 : k + 1;
  }
  const double slope = std::max(drop - quantum, 0.0) / static_cast<double>(steps);
  return slope * static_cast<double>(run) / 2.0;
}

}  // namespace

std::size_t clipped_samples(const std::vector<double>& v) {
  const auto [low, high] = std::minmax_element(v.begin(), v.end());
  if (low == v.end() || *low == *high) return 0;  // a constant has no full scale to hit
  // The resolution: the smallest change between two samples (a quantum of a quantized signal).
  double quantum = *high - *low;
  for (std::size_t i = 1; i < v.size(); ++i) {
    const double change = std::fabs(v[i] - v[i - 1]);
    if (change > 0.0) quantum = std::min(quantum, change);
  }
  std::size_t clipped = 0;
  for (std::size_t i = 0; i < v.size();) {
    std::size_t end = i + 1;
    while (end < v.size() && v[end] == v[i]) ++end;
    if (end - i >= 3 && (v[i] == *low || v[i] == *high)) {
      const double before = carried_past(v, i, end, -1, v[i], quantum);
      const double after = carried_past(v, i, end, +1, v[i], quantum);
      const double limit = kClippedQuanta * quantum;
      // Every side the run has must have run into it.
      if ((before < 0 || before > limit) && (after < 0 || after > limit) &&
          (before >= 0 || after >= 0))
        clipped += end - i;
    }
    i = end;
  }
  return clipped;
}

std::vector<SampledSignal> condition_series(const std::string& path, RawSeries raw,
                                            const RecordingOptions& options,
                                            RecordingReport& report) {
  check_times(path, raw);
  report.source = raw.source;
  report.samples_read = raw.t_s.size();
  report.frames_too_short = raw.frames_too_short;
  if (options.quantity == Quantity::length) {
    if (!length_unit_factor(raw.unit, report.unit_factor)) {
      throw HostError(fmt::format("{}: {} has unit '{}', not a length (m, mm, cm, um)", path,
                                  raw.source, raw.unit));
    }
  } else if (!acceleration_unit_factor(raw.unit, report.unit_factor)) {
    throw HostError(
        fmt::format("{}: {} has unit '{}', not an acceleration (g, m/s^2, mm/s^2); "
                    "give --unit to read it as one",
                    path, raw.source, raw.unit));
  }
  if (report.unit_factor != 1.0)
    for (double& v : raw.values) v *= report.unit_factor;
  report.clipped_samples = clipped_samples(raw.values);
  const double step = nominal_step(raw.t_s);
  report.source_rate_hz = 1.0 / step;
  for (std::size_t i = 1; i < raw.t_s.size(); ++i) {
    const double gap = raw.t_s[i] - raw.t_s[i - 1];
    if (gap > kGapSteps * step) {
      if (report.gaps++ == 0) {
        report.first_gap_t_s = raw.t_s[i - 1];
        report.first_gap_length_s = gap;
      }
    } else {
      report.jitter_max = std::max(report.jitter_max, std::fabs(gap - step) / step);
    }
  }
  if (report.gaps > 0 && options.gaps == GapPolicy::refuse) {
    throw HostError(fmt::format(
        "{}: gap after t = {} s: {:.6g} s without samples (the step is {:.6g} s; {} gap{} in "
        "all); "
        "--gaps hold repeats the last value, --gaps split runs each part alone",
        path, report.first_gap_t_s, report.first_gap_length_s, step, report.gaps,
        report.gaps == 1 ? "" : "s"));
  }
  std::vector<SampledSignal> segments;
  for (Part& part : parts_at_gaps(raw, step, options, report)) {
    if (part.t_s.size() < 2) {
      report.short_segment_samples += part.t_s.size();
      continue;
    }
    segments.push_back(
        onto_model_step(path, std::move(part), step, raw.time_origin_s, options, report));
  }
  if (segments.empty()) throw HostError(path + ": no part between the gaps has 2 samples");
  report.segments = segments.size();
  // The force stays with its samples only when they are the file's own: one part, nothing held,
  // regridded or resampled.
  if (!raw.f_a_n.empty()) {
    if (segments.size() == 1 && report.held_samples == 0 && report.regridded_samples == 0 &&
        !report.resampled && segments.front().a_u_m_per_s2.size() == raw.f_a_n.size()) {
      segments.front().f_a_n = std::move(raw.f_a_n);
    } else {
      report.actuator_force_unaligned = true;
    }
  }
  return segments;
}

std::string describe_recording(const std::string& path, const RecordingReport& r) {
  if (!r.acted()) return "";
  std::string text = fmt::format("{}: {}, {} samples at {:.6g} Hz", path, r.source, r.samples_read,
                                 r.source_rate_hz);
  if (r.regridded_samples > 0) {
    text += fmt::format("; jitter up to {:.3g} %: {} samples put on a uniform grid (cubic spline)",
                        100.0 * r.jitter_max, r.regridded_samples);
  }
  if (r.resampled) text += fmt::format("; resampled to {:.6g} Hz (libsoxr VHQ)", r.resampled_to_hz);
  if (r.gaps > 0) {
    text += fmt::format("; {} gap{} (first after t = {} s, {:.6g} s long)", r.gaps,
                        r.gaps == 1 ? "" : "s", r.first_gap_t_s, r.first_gap_length_s);
  }
  if (r.held_samples > 0) text += fmt::format("; {} samples held over gaps", r.held_samples);
  if (r.segments > 1) text += fmt::format("; split into {} segments", r.segments);
  if (r.short_segment_samples > 0) {
    text += fmt::format("; {} samples in parts shorter than 2 samples not run",
                        r.short_segment_samples);
  }
  if (r.clipped_samples > 0) {
    text += fmt::format("; {} samples in runs at the minimum or maximum (clipping?)",
                        r.clipped_samples);
  }
  if (r.frames_too_short > 0)
    text += fmt::format("; {} frames too short for the signal", r.frames_too_short);
  return text;
}

std::string recording_report_json(const RecordingReport& r) {
  nlohmann::ordered_json json;
  json["source"] = r.source;
  json["samples_read"] = r.samples_read;
  json["source_rate_hz"] = r.source_rate_hz;
  json["jitter_max"] = r.jitter_max;
  json["unit_factor"] = r.unit_factor;
  json["regridded_samples"] = r.regridded_samples;
  json["resampled"] = r.resampled;
  json["resampled_to_hz"] = r.resampled_to_hz;
  json["gaps"] = r.gaps;
  json["first_gap_t_s"] = r.first_gap_t_s;
  json["first_gap_length_s"] = r.first_gap_length_s;
  json["held_samples"] = r.held_samples;
  json["segments"] = r.segments;
  json["short_segment_samples"] = r.short_segment_samples;
  json["clipped_samples"] = r.clipped_samples;
  json["frames_too_short"] = r.frames_too_short;
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace stickslip::host
