// The ECU node of lib/ (stickslip/can/ecu_node.hpp) behind a CAN receive callback: SeatInput
// frames of docs/can/stickslip.dbc in (E2E CRC and counters checked as the host node checks
// them, lost samples held), one seat step per sample, SeatMotion and SeatForce out (the DBC's
// layout and E2E fields), and SeatStats and SeatScene every tenth sample as the host node sends
// them (the Cortex-M4F's from its observer, the Cortex-M0+'s from its window over its words).
// Frames with other identifiers are counted and ignored. Everything statically allocated; no heap,
// no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/can/frame.hpp"

extern "C" {
// Configures the model (the reference seat, stick-slip, F_fk = F_fs = 45 N, dt = 1 ms, exact
// integrator; built with STICKSLIP_FIRMWARE_END_STOPS, the seat of
// docs/scenes/seat-with-end-stops.toml) and the node, and resets them. Returns 0, or the
// configure() Status as a number (Status::unsupported: the seat needs a finer event search than the
// build's bound takes).
int stickslip_node_start();
// The seat's step for one sample (the node calls it; the step budget is measured from it).
// Declared in node.cpp (its argument is the build's scalar).
// The CAN receive callback: checks the frame and, for every sample it brings, steps the seat,
// calls board_can_send() with each output frame, then board_node_sampled().
void stickslip_node_on_frame(const stickslip::can::Frame* frame);
// The outputs of the last step, bit for bit, for comparing targets (kNodeRecordBytes bytes, little
// endian): x_r, v_r, a_x, f_f, stuck time, stuck fraction as 8 bytes each (fixed point: the raw
// int64; float: the IEEE bits, zero-extended), then stuck, events, saturated so far.
void stickslip_node_record(std::uint8_t* out);
}
inline constexpr std::size_t kNodeRecordBytes = 6 * 8 + 3;
