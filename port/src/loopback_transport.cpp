// Placeholder until the loopback bus lands.
#include "stickslip/port/loopback_transport.hpp"

#include "stickslip/port/socketcan_transport.hpp"

namespace stickslip::port {

std::unique_ptr<Transport> make_loopback_transport() { return make_socketcan_transport(); }

}  // namespace stickslip::port
