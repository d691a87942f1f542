// The in-process loopback bus: the default bus where the kernel has no CAN support. Every
// endpoint on a bus receives what the other endpoints send (never its own frames), in order,
// through a bounded receive queue whose overflow is counted as receive_drops. It carries what a
// CAN FD controller could (classic, FD, remote and error frames), so faults can be injected
// through it; frames are timestamped (steady clock, ns) when sent.
#pragma once

#include <cstddef>
#include <memory>

#include "stickslip/port/transport.hpp"

namespace stickslip::port {

inline constexpr std::size_t kLoopbackDefaultQueueFrames = 4096;

// An unopened endpoint; open("loopback") attaches it to the process-wide loopback bus.
std::unique_ptr<Transport> make_loopback_transport();
// The same with a receive queue of `queue_frames` (>= 1) frames.
std::unique_ptr<Transport> make_loopback_transport(std::size_t queue_frames);

// Endpoints open on the loopback bus now (lets a test wait until a node is listening).
std::size_t loopback_endpoints() noexcept;

}  // namespace stickslip::port
