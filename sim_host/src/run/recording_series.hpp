// Private to recording_source: one signal of a file as read, before gaps and resampling.
#pragma once

#include <string>
#include <vector>

#include "stickslip/host/io/delimited_text.hpp"
#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

struct RawSeries {
  std::vector<double> t_s;
  std::vector<double> values;  // in the file's unit
  std::string unit;            // as the file or --unit names it; empty: m/s^2 assumed
  std::string source;
  std::size_t frames_too_short = 0;
  bool from_rate = false;           // t made from --rate
  std::vector<std::size_t> lines;   // text: the file's line of each sample (messages name it)
  std::vector<std::size_t> frames;  // CAN log: each sample's frame (SignalSeries::frames)
  bool frame_lines = false;         // frames are lines of a text log, not places in a BLF
  // The clock's reading at t = 0 when the times are offsets from a larger one (a BLF's start
  // time since the epoch), else 0: their rounding is that of the clock (steps_uniform).
  double time_origin_s = 0.0;
  std::vector<double> f_a_n;  // text: a column f_a (actuator force, N), when there is one
};

// A text table's time column: --time NAME, else the first column named t or time or in s or ms;
// nullptr if there is none. With --rate, a table that has one is refused (--rate would replace
// its times and hide its gaps).
const TextChannel* text_time_column(const std::string& path, const DelimitedTable& table,
                                    const RecordingOptions& options);

// Text (delimited_text.hpp) or a CAN log with a DBC (can_signal.hpp), as `options` select.
RawSeries read_raw_series(const std::string& path, const RecordingOptions& options);

// The median of the steps t[i] - t[i-1] (t.size() >= 2).
double median_step(const std::vector<double>& t);
// The nominal step: the mean of the steps that are no gap (<= kGapSteps medians). The median
// alone is biased where times are quantized, as candump's seconds since the epoch are in a
// double (steps of 0.002 s come out as 8388 or 8389 ulps of 2.4e-7 s); the mean is not.
double nominal_step(const std::vector<double>& t);
// Samples in runs of at least 3 equal values at the minimum or maximum (full scale) that the
// signal ran into: its slope on each side of the run, measured over two quanta of its resolution
// (the smallest change between samples), would have carried it more than 4 quanta past the
// run's level by the run's middle. A quantized signal's smooth peak, which dwells at its top
// level, is no clipping.
std::size_t clipped_samples(const std::vector<double>& values);

// Checks the times, finds gaps and jitter, converts the unit, and puts every segment on the
// model's step as `options` say; fills `report`.
std::vector<SampledSignal> condition_series(const std::string& path, RawSeries raw,
                                            const RecordingOptions& options,
                                            RecordingReport& report);

}  // namespace stickslip::host
