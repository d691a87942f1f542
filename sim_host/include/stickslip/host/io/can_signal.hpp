// One signal of a CAN log as a time series: the frames of the signal's message (by id and id
// width) among all the other traffic, each decoded with the DBC into the signal's unit.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "stickslip/host/io/can_log.hpp"
#include "stickslip/host/io/dbc.hpp"

namespace stickslip::host {

struct SignalSeries {
  std::string name;  // "MESSAGE.SIGNAL"
  std::string unit;  // the DBC's unit of the signal
  std::vector<double> t_s;
  std::vector<double> values;
  // Per sample: the frame's line in a text log, or its 1-based place among the log's data
  // frames in a BLF file (frame_lines says which), for messages that name a frame.
  std::vector<std::size_t> frames;
  bool frame_lines = false;
  std::size_t frames_too_short = 0;  // frames of the message whose data cannot hold the signal
};

// `selector` is "MESSAGE.SIGNAL" as the DBC names them. Throws HostError when the DBC has no
// such signal, or the log (named `log_path` in the message) has no frame that carries it.
// `channel` (the --channel option) keeps the frames of that bus only; a channel the log does not
// have is a UsageError naming the log's channels. Without it, a message on more than one
// channel is a UsageError naming them: two buses merged into one stream would be no signal.
SignalSeries extract_signal(const CanLog& log, const std::string& log_path, const Dbc& dbc,
                            std::string_view selector, std::string_view channel = {});

// Throws UsageError "--channel NAME: FILE has no frame on that channel (its channels: ...)" when
// `channel` (the --channel option) is given and no data frame of the log is on it.
void require_channel(const CanLog& log, const std::string& log_path, std::string_view channel);

}  // namespace stickslip::host
