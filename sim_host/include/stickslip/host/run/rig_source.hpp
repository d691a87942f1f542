// A rig recording read the way every command reads a recording (recording_source.hpp): any format
// the readers accept (a logger's text, a CAN log with its DBC), each channel picked by name with
// its unit, the same time column or --rate, gap policy and resampling to the model's step for
// a_u, a_x and x_r alike. With no option given the file is read exactly as read_rig_recording()
// reads it (rig_recording.hpp), its checks included. docs/IDENTIFICATION.md.
#pragma once

#include <string>

#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

struct RigSourceOptions {
  // a_u's --signal and --unit, and what all channels share: --dbc, --time, --rate, --gaps, --dt.
  RecordingOptions recording;
  std::string ax_signal;      // text: column name or index (default a_x); CAN: MESSAGE.SIGNAL
  std::string ax_unit;        // g | m/s^2 | mm/s^2 over the header's or DBC's
  std::string travel_signal;  // text default: a column x_r when there is one; CAN: none
  std::string travel_unit;    // m | mm | cm | um over the header's or DBC's
  bool defaults() const noexcept;
};

struct RigSource {
  RigRecording rig;
  // What was done to each channel's samples (recording_source.hpp); x_r's only with travel.
  RecordingReport a_u, a_x, x_r;
};

// Throws HostError naming the file for bad data (a channel missing, a unit that is no
// acceleration or length, channels whose samples do not line up, fewer than 16 samples) and
// UsageError for options that contradict the file.
RigSource read_rig_source(const std::string& path, const RigSourceOptions& options);

}  // namespace stickslip::host
