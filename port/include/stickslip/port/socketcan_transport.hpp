// SocketCAN (Linux AF_CAN, CAN_RAW) endpoint on a named interface such as vcan0.
//
// open() sets everything up once, outside the receive loop (as can-utils' candump does):
//   CAN_RAW_FD_FRAMES   on, so CAN FD frames arrive whole and are reported with kFd (the node
//                       refuses and counts them; they are never truncated to 8 bytes);
//   CAN_RAW_ERR_FILTER  every error class, reported as frames with kErrorFrame (id = the
//                       error class bits, data = the kernel's error details);
//   SO_TIMESTAMPNS      kernel receive time in frame.timestamp_ns (SO_TIMESTAMP as fallback);
//   SO_RXQ_OVFL         the socket's drop count, read from every message's control data into
//                       counters().receive_drops (the kernel reports it with the next frame
//                       that does arrive, so drops show once reading resumes).
// Every read must be exactly CAN_MTU or CANFD_MTU bytes with a valid length; anything else is
// counted in malformed_reads and returned as io_error. All calls are noexcept and map every
// error number to a TransportStatus:
//   open:    unsupported (no AF_CAN / CAN_RAW in this kernel), no_such_interface (unknown
//            name, or the interface is down), invalid_argument (empty or too long a name),
//            io_error (anything else)
//   send:    closed (not open), invalid_argument (error frame, bad id, bad length, FD frame on
//            a classic-only interface), buffer_full (EAGAIN/ENOBUFS: the queue is full),
//            interface_down (ENETDOWN), no_such_interface (ENODEV/ENXIO: the interface is gone),
//            io_error
//   receive: closed, timeout, interface_down (ENETDOWN: the kernel reports the interface going
//            down once, as a socket error; the socket stays bound, frames queued before are
//            still read, and frames arrive again once it is up), no_such_interface (ENODEV: the
//            interface was deleted and the socket unbound; open() again), io_error (malformed
//            read, other errors)
#pragma once

#include <memory>
#include <string>

#include "stickslip/port/transport.hpp"

namespace stickslip::port {

// True when this kernel can open an AF_CAN raw socket at all.
bool kernel_has_can() noexcept;

// True when kernel_has_can() and `interface_name` names an interface that is up.
bool can_interface_is_up(const std::string& interface_name) noexcept;

struct SocketCanOptions {
  // SO_RCVBUF in bytes (0: the kernel's default). The kernel doubles the value and enforces a
  // minimum; a small buffer makes overflow (receive_drops) easy to provoke in tests.
  int receive_buffer_bytes = 0;
};

// An unopened SocketCAN endpoint (open() returns unsupported where kernel_has_can() is false).
std::unique_ptr<Transport> make_socketcan_transport();
std::unique_ptr<Transport> make_socketcan_transport(const SocketCanOptions& options);

}  // namespace stickslip::port
