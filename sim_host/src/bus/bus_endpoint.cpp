#include "bus_endpoint.hpp"

#include <fmt/format.h>

#include <chrono>
#include <thread>

#include "stickslip/host/error.hpp"
#include "stickslip/port/socketcan_transport.hpp"

namespace stickslip::host {

std::unique_ptr<port::Transport> open_bus(const std::string& bus, const char* option,
                                          int receive_buffer_bytes) {
  port::SocketCanOptions options;
  options.receive_buffer_bytes = receive_buffer_bytes;
  std::unique_ptr<port::Transport> transport = bus == "loopback" || receive_buffer_bytes <= 0
                                                   ? port::make_transport(bus)
                                                   : port::make_socketcan_transport(options);
  const port::TransportStatus status = transport->open(bus);
  if (status != port::TransportStatus::ok) {
    // "unsupported" alone does not say that the name is what was wrong.
    throw HostError(fmt::format(
        "{} {}: cannot open the bus: {} (expected loopback or a CAN interface of this machine, "
        "such as vcan0; `ip link show type vcan` lists them)",
        option, bus, port::transport_status_name(status)));
  }
  return transport;
}

port::TransportStatus send_frame(port::Transport& transport, const can::Frame& frame) {
  port::TransportStatus status = transport.send(frame);
  for (int attempt = 0; status == port::TransportStatus::buffer_full && attempt < 100; ++attempt) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    status = transport.send(frame);
  }
  return status;
}

}  // namespace stickslip::host
