// can-utils' candump log format ("(sec.usec) iface ID#hexdata", as `candump -l` writes and
// `canplayer` reads): the project reads such logs as recordings and writes them for canplayer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stickslip/can/frame.hpp"

namespace stickslip::host {

struct LoggedFrame {
  std::uint64_t time_us = 0;  // (sec.usec) as microseconds since the epoch the log uses
  std::string interface;      // e.g. "vcan0"
  can::Frame frame;           // timestamp_ns = time_us * 1000
};

// Reads every line; throws HostError naming the file and line for a line that is not a valid
// classic, FD, remote or error frame record.
std::vector<LoggedFrame> read_candump_log(const std::string& path);

// Writes one line per frame, in order, atomically (as output_file.hpp does).
void write_candump_log(const std::string& path, const std::vector<LoggedFrame>& frames);

}  // namespace stickslip::host
