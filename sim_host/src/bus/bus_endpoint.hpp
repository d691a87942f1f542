// Opening a bus by name and sending on it, as replay, ecu and play do. Private to the bus
// library.
#pragma once

#include <memory>
#include <string>

#include "stickslip/can/frame.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::host {

// "loopback" or a SocketCAN interface; receive_buffer_bytes > 0: SO_RCVBUF of a SocketCAN
// endpoint (the loopback bus has none). Throws HostError "OPTION BUS: cannot open the bus: ...".
std::unique_ptr<port::Transport> open_bus(const std::string& bus, const char* option,
                                          int receive_buffer_bytes = 0);

// Throws UsageError "OPTION: must be a positive time step in s, got X" unless dt_s > 0, finite.
void require_positive_dt(double dt_s, const char* option);

// Sends, retrying briefly while the socket's queue is full (a real bus drains it).
port::TransportStatus send_frame(port::Transport& transport, const can::Frame& frame);

}  // namespace stickslip::host
