// SocketCAN (Linux AF_CAN, CAN_RAW) endpoint on a named interface such as vcan0.
#pragma once

#include <memory>
#include <string>

#include "stickslip/port/transport.hpp"

namespace stickslip::port {

// True when this kernel can open an AF_CAN raw socket at all.
bool kernel_has_can() noexcept;

// An unopened SocketCAN endpoint (open() returns unsupported where kernel_has_can() is false).
std::unique_ptr<Transport> make_socketcan_transport();

}  // namespace stickslip::port
