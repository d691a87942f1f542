// Private to recording_source: one signal of a file as read, before gaps and resampling.
#pragma once

#include <string>
#include <vector>

#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

struct RawSeries {
  std::vector<double> t_s;
  std::vector<double> values;  // in the file's unit
  std::string unit;            // as the file or --unit names it; empty: m/s^2 assumed
  std::string source;
  std::size_t frames_too_short = 0;
  bool from_rate = false;  // t made from --rate
};

// Text (delimited_text.hpp) or a CAN log with a DBC (can_signal.hpp), as `options` select.
RawSeries read_raw_series(const std::string& path, const RecordingOptions& options);

// Checks the times, finds gaps and jitter, converts the unit, and puts every segment on the
// model's step as `options` say; fills `report`.
std::vector<SampledSignal> condition_series(const std::string& path, RawSeries raw,
                                            const RecordingOptions& options,
                                            RecordingReport& report);

}  // namespace stickslip::host
