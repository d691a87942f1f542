// The seat model behind a CAN receive callback: one input frame in, one step of the model, one
// output frame out. Everything statically allocated; no heap, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/can/frame.hpp"

// Identifiers and payloads of the example (little endian):
//   in  0x120: int16 a_u in mm/s^2 (bytes 0-1)
//   out 0x121: int16 a_x in mm/s^2 (bytes 0-1), stuck (byte 2), events in the step (byte 3),
//              saturated so far (byte 4: fixed point only; 0 for float)
// A plain decode without the E2E protection (CRC and counters) of docs/can/stickslip.dbc: the
// example shows the model's cost on the target; the callback itself does not depend on the payload.
inline constexpr std::uint32_t kNodeInputId = 0x120;
inline constexpr std::uint32_t kNodeOutputId = 0x121;

extern "C" {
// Configures the model (the reference seat, stick-slip, F_fk = F_fs = 45 N, dt = 1 ms, exact
// integrator) and resets it to rest. Returns 0, or the configure() Status as a number.
int stickslip_node_start();
// The CAN receive callback: frames other than kNodeInputId with 2+ bytes are ignored. Calls
// board_can_send() with the output frame.
void stickslip_node_on_frame(const stickslip::can::Frame* frame);
// The outputs of the last step, bit for bit, for comparing targets (kNodeRecordBytes bytes, little
// endian): x_r, v_r, a_x, f_f, stuck time, stuck fraction as 8 bytes each (fixed point: the raw
// int64; float: the IEEE bits, zero-extended), then stuck, events, saturated so far.
void stickslip_node_record(std::uint8_t* out);
}
inline constexpr std::size_t kNodeRecordBytes = 6 * 8 + 3;
