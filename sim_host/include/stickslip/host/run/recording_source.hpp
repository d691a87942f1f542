// The one way every command reads a recording: a file (the project's t,a_u CSV, a logger's
// delimited text, .mat, or a CAN log with a DBC), one signal of it in m/s^2, its gaps handled by
// a stated policy, and its samples put on the model's step (resample.hpp). Every act on the data
// (resampling, samples held across a gap, segments split, runs at full scale) is counted in a
// RecordingReport that the commands print (a stderr line, JSON keys). docs/RECORDINGS.md.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "stickslip/host/io/csv_reader.hpp"

namespace stickslip::host {

enum class GapPolicy { refuse, hold, split };
// What the signal measures: an acceleration (m/s^2; g and mm/s^2 converted) or, for a rig's
// travel x_r, a length (m; mm converted).
enum class Quantity { acceleration, length };

struct RecordingOptions {
  std::string signal;   // text: column name or 1-based index; CAN log: MESSAGE.SIGNAL
  std::string dbc;      // a CAN log's DBC; given: the file is read as a CAN log
  std::string channel;  // a CAN log's bus (LogFrame::channel): only its frames are decoded
  std::string time;     // text: the time column (default: one called t or time, or unit s)
  double rate_hz = 0;   // text without a time column: the sample rate (0: not given)
  std::string unit;     // g | m/s^2 | mm/s^2, over the header's or the DBC's unit
  GapPolicy gaps = GapPolicy::refuse;
  double dt_s = 0;  // the model's step (0: the recording's own, which must be uniform)
  Quantity quantity = Quantity::acceleration;
  // Whether nothing was given: today's t,a_u CSV and .mat are then read exactly as before.
  bool defaults() const noexcept;
};

// A step longer than this many nominal (median) steps is a gap.
inline constexpr double kGapSteps = 1.5;
// Steps within this relative distance of the nominal step are uniform (no regridding); the same
// tolerance as CsvReader's uniform check.
inline constexpr double kJitterTolerance = kUniformStepTolerance;

// Whether steps whose largest relative distance from the nominal `step_s` is `jitter` are
// uniform: within kJitterTolerance, or within what times as large as t_first_s and t_last_s can
// tell apart in a double (two of its spacings there). A candump log's seconds since the epoch
// (about 1.8e9 s, spaced 2.4e-7 s) cannot show a 1 ms step to better than 2.4e-4 of it.
bool steps_uniform(double jitter, double step_s, double t_first_s, double t_last_s) noexcept;

struct RecordingReport {
  std::string source;  // "text column AccZ [g]", "CAN CabFloor.AccZ [g]", "t,a_u CSV"
  std::size_t samples_read = 0;
  double source_rate_hz = 0;          // 1 / the median step
  double jitter_max = 0;              // max |step - median| / median over the steps that are no gap
  double unit_factor = 1;             // m/s^2 per unit of the file
  std::size_t regridded_samples = 0;  // samples the spline put on the uniform grid
  bool resampled = false;             // libsoxr changed the rate
  double resampled_to_hz = 0;
  std::size_t gaps = 0;
  double first_gap_t_s = 0, first_gap_length_s = 0;
  std::size_t held_samples = 0;  // --gaps hold: samples that repeat the last value before a gap
  // In runs of >= 3 equal samples at the minimum or maximum that the signal ran into (not a
  // quantized signal's smooth peak, recording_series.hpp)
  std::size_t clipped_samples = 0;
  std::size_t segments = 1;
  std::size_t short_segment_samples = 0;  // --gaps split: samples of parts too short to run
  std::size_t frames_too_short = 0;       // CAN: frames of the message that cannot hold the signal
  // A text column f_a (actuator force) that could not stay on its samples: the signal was held,
  // split, regridded or resampled. simulate refuses such a file; the others do not use f_a.
  bool actuator_force_unaligned = false;
  bool acted() const noexcept;  // anything beyond reading the samples as they are
};

struct LoadedRecording {
  std::vector<SampledSignal> segments;  // one unless --gaps split cut it
  RecordingReport report;
};

// Reads, converts, handles gaps and resamples as `options` say. Throws HostError naming the file
// (and line, frame, sample or gap) for bad data, UsageError for options that contradict the file.
LoadedRecording read_recording(const std::string& path, const RecordingOptions& options);

// The one segment of a recording read with gaps refused or held (--gaps split is refused with a
// UsageError naming `command`, for the bus commands, which stream one continuous signal).
SampledSignal read_continuous_recording(const std::string& path, const RecordingOptions& options,
                                        const char* command, RecordingReport* report = nullptr);

// An actuator force column (f_a) runs only on a recording read as it is: one part, on its own
// step, nothing held, regridded or resampled, so each force stays on its sample. Refuses
// anything else, naming the file (simulate and the Python module).
void require_force_as_read(const std::string& path, const LoadedRecording& recording);

// A scene's sample rate (scene_dt_s > 0) against the step dt_s of the recording read with
// `options`: HostError naming both files and both steps, and the --dt that resamples the
// recording to the scene's rate. A --dt given (options.dt_s > 0) overrides the scene's rate.
void check_scene_rate(const std::string& path, const RecordingOptions& options, double dt_s,
                      const std::string& scene_path, double scene_dt_s);

// "IN: resampled 500 Hz -> 1000 Hz (libsoxr VHQ), 12 samples regridded (jitter 3.0 %), ..." or
// "" when nothing was done to the samples.
std::string describe_recording(const std::string& path, const RecordingReport& report);
// The report as a JSON object (one line) for the commands' statistics.
std::string recording_report_json(const RecordingReport& report);

// The parsed --unit or header unit: m/s^2 per unit; false for a unit that is no acceleration.
bool acceleration_unit_factor(const std::string& unit, double& factor);
// m per unit for a length (m, mm, cm, um); an empty unit is m.
bool length_unit_factor(const std::string& unit, double& factor);
// The factor of `unit` for `quantity` (one of the two above).
bool unit_factor(Quantity quantity, const std::string& unit, double& factor);
// "refuse" | "hold" | "split"
bool parse_gap_policy(const std::string& text, GapPolicy& policy);

}  // namespace stickslip::host
