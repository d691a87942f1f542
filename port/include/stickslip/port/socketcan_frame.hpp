// The SocketCAN endpoint's conversions between can::Frame and the kernel's struct can_frame /
// struct canfd_frame, as pure functions (Linux headers only, no socket), so the checks on
// every read and every send can be tested on any host, also one without AF_CAN.
#pragma once

#include <linux/can.h>

#include <cstddef>

#include "stickslip/can/frame.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::port {

// True for the data lengths a CAN FD DLC can express: 0..8, 12, 16, 20, 24, 32, 48, 64.
bool is_fd_length(unsigned length) noexcept;

// One read from a CAN_RAW socket: `size` bytes of `raw` (`truncated`: the kernel flagged
// MSG_TRUNC). Exactly CAN_MTU with a length <= 8 is a classic frame, exactly CANFD_MTU with a
// length a DLC can express an FD frame (kFd); anything else is malformed and `frame` is left
// unchanged. Error frames get kErrorFrame and the error class bits as id; timestamp_ns is 0.
bool decode_socketcan_read(const canfd_frame& raw, std::size_t size, bool truncated,
                           can::Frame& frame) noexcept;

// The bytes to write for `frame`: classic frames as CAN_MTU bytes, FD frames as CANFD_MTU.
// invalid_argument for a frame no bus can carry: an error frame, an id wider than its format,
// more than 8 bytes in a classic frame, an FD length no DLC expresses, a remote FD frame.
TransportStatus encode_socketcan_write(const can::Frame& frame, canfd_frame& raw,
                                       std::size_t& size) noexcept;

}  // namespace stickslip::port
