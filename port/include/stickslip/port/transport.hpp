// The transport every bus offers the host tools and the ECU node: open a named bus, send and
// receive single frames with a timeout, close. No exceptions: every call returns a status, and
// the counters say what the port itself saw (drops, malformed reads).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "stickslip/can/frame.hpp"

namespace stickslip::port {

enum class TransportStatus : std::uint8_t {
  ok,
  timeout,            // receive: nothing arrived within the timeout
  closed,             // not open, or closed while waiting
  unsupported,        // this platform/kernel has no such bus (e.g. no AF_CAN)
  no_such_interface,  // open: the named interface does not exist (or is down)
  invalid_argument,   // a frame the bus cannot carry (length > 8 on a classic bus, bad id ...)
  buffer_full,        // send: the bus/socket would block and the frame was not sent
  io_error,           // any other failure of the platform call
  interface_down,     // send/receive: the interface went down (SocketCAN ENETDOWN); the endpoint
                      // stays bound and carries frames again once the interface is up
};
const char* transport_status_name(TransportStatus status) noexcept;

// Accept a frame when (frame.id & mask) == (id & mask) (the SocketCAN rule).
struct ReceiveFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;  // 0 accepts every id
};

struct TransportCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t receive_drops = 0;    // frames the bus lost before we read them (SO_RXQ_OVFL, or
                                      // the loopback receive queue was full)
  std::uint64_t malformed_reads = 0;  // reads that were not exactly one whole frame
  std::uint64_t send_failures = 0;    // send() calls that returned a status other than ok
};

class Transport {
 public:
  virtual ~Transport() = default;
  // bus_name: "loopback" (the in-process bus) or a SocketCAN interface such as "vcan0".
  virtual TransportStatus open(const std::string& bus_name) noexcept = 0;
  // Replaces the receive filters (count 0: accept everything). Call after open().
  virtual TransportStatus set_filters(const ReceiveFilter* filters, std::size_t count) noexcept = 0;
  virtual TransportStatus send(const can::Frame& frame) noexcept = 0;
  // timeout_ms = 0 polls, < 0 waits without limit. On ok, frame.timestamp_ns is set.
  virtual TransportStatus receive(can::Frame& frame, int timeout_ms) noexcept = 0;
  virtual void close() noexcept = 0;
  virtual TransportCounters counters() const noexcept = 0;
};

// "loopback" gives an endpoint on the process-wide loopback bus (every endpoint receives what
// the others send, like a CAN bus; never its own frames); any other name a SocketCAN endpoint.
// The transport is returned unopened.
std::unique_ptr<Transport> make_transport(const std::string& bus_name);

// The bus a command uses when none is named: "vcan0" when the kernel has CAN and that
// interface exists, else "loopback".
std::string default_bus_name();

}  // namespace stickslip::port
