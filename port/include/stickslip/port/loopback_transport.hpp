// The in-process loopback bus: the default bus where the kernel has no CAN support. Every
// endpoint on a bus receives what the other endpoints send (never its own frames), in order,
// through a bounded receive queue whose overflow is counted as receive_drops.
#pragma once

#include <memory>

#include "stickslip/port/transport.hpp"

namespace stickslip::port {

// An unopened endpoint; open("loopback") attaches it to the process-wide loopback bus.
std::unique_ptr<Transport> make_loopback_transport();

}  // namespace stickslip::port
