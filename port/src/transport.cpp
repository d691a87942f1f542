#include "stickslip/port/transport.hpp"

#include "stickslip/port/loopback_transport.hpp"
#include "stickslip/port/socketcan_transport.hpp"

namespace stickslip::port {

const char* transport_status_name(TransportStatus status) noexcept {
  switch (status) {
    case TransportStatus::ok:
      return "ok";
    case TransportStatus::timeout:
      return "timeout";
    case TransportStatus::closed:
      return "closed";
    case TransportStatus::unsupported:
      return "unsupported";
    case TransportStatus::no_such_interface:
      return "no such interface";
    case TransportStatus::invalid_argument:
      return "invalid argument";
    case TransportStatus::buffer_full:
      return "buffer full";
    case TransportStatus::io_error:
      return "i/o error";
    case TransportStatus::interface_down:
      return "interface down";
  }
  return "unknown";
}

std::unique_ptr<Transport> make_transport(const std::string& bus_name) {
  if (bus_name == "loopback") return make_loopback_transport();
  return make_socketcan_transport();
}

std::string default_bus_name() {
  return can_interface_is_up("vcan0") ? "vcan0" : "loopback";
}

}  // namespace stickslip::port
