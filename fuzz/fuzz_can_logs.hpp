// What the CAN log fuzz targets check on whatever a reader accepts: every frame keeps the
// promises of host/io/can_log.hpp (ids within their width, at most 8 data bytes, as many as
// the DLC says up to 8, a finite time, a known direction).
#pragma once

#include <cmath>

#include "stickslip/host/io/can_log.hpp"

#include "fuzz_support.hpp"

namespace stickslip::fuzz {

inline void check_log(const host::CanLog& log) {
  for (const host::LogFrame& frame : log.frames) {
    check(frame.id <= (frame.extended ? 0x1FFFFFFFu : 0x7FFu));
    check(frame.length <= 8 && frame.dlc <= 15);
    check(frame.length == (frame.dlc < 8 ? frame.dlc : 8));
    check(std::isfinite(frame.time_s));
    check(frame.direction == 0 || frame.direction == 'R' || frame.direction == 'T');
  }
}

}  // namespace stickslip::fuzz
