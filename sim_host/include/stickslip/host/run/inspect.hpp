// `stickslip inspect`: what a recording holds and how to simulate it - its channels or CAN
// signals with units, the sample rate and duration, the timestamps' jitter (min/median/max step),
// gaps, runs at full scale, NaNs - and the simulate command line that reads it, ready to paste.
#pragma once

#include <string>

#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

// The model's step inspect proposes when the recording's rate is another (1 kHz, the project's
// default sample rate).
inline constexpr double kSuggestedDtS = 1e-3;

// The report as text, its last line the suggested command ("stickslip simulate ..."). `options`
// may name the DBC, the time column or the rate, and the signal to describe first.
std::string inspect_recording(const std::string& path, const RecordingOptions& options);

}  // namespace stickslip::host
