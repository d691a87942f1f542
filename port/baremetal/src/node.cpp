#include "node.hpp"

#include <cstring>

#include "board.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

#if defined(STICKSLIP_FIRMWARE_FIXED)
using Scalar = stickslip::Fixed;  // Cortex-M0+: no FPU
#else
using Scalar = float;  // Cortex-M4F: single-precision FPU
#endif
using Seat = stickslip::Oscillator<Scalar, stickslip::CoulombStickSlip>;

Seat seat;  // the model's coefficients and state, statically allocated (no heap)
stickslip::StepOutput<Scalar> last_output{};

constexpr Scalar kPerMilli = Scalar(0.001);  // mm/s^2 -> m/s^2
constexpr Scalar kThousand = Scalar(1000);

// v * 1000 rounded to the nearest integer and clamped to int16.
std::int16_t to_milli(Scalar v) {
  const Scalar scaled = v * kThousand;
  std::int32_t rounded = 0;
#if defined(STICKSLIP_FIRMWARE_FIXED)
  const std::int64_t raw = scaled.raw();
  const std::int64_t half = std::int64_t{1} << (Scalar::kFractionBits - 1);
  const std::int64_t magnitude = ((raw < 0 ? -raw : raw) + half) >> Scalar::kFractionBits;
  const std::int64_t clamped = magnitude > 32767 ? 32767 : magnitude;
  rounded = static_cast<std::int32_t>(raw < 0 ? -clamped : clamped);
#else
  const float clamped = scaled > 32767.0f ? 32767.0f : (scaled < -32767.0f ? -32767.0f : scaled);
  rounded = static_cast<std::int32_t>(clamped + (clamped < 0.0f ? -0.5f : 0.5f));
#endif
  return static_cast<std::int16_t>(rounded);
}

}  // namespace

extern "C" int stickslip_node_start() {
  stickslip::OscillatorParams params;  // the reference seat
  params.model = stickslip::FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = 45.0;
  params.dt_s = 1e-3;
  params.integrator = stickslip::Integrator::exact;
  const stickslip::ConfigResult result = seat.configure(params);
  return static_cast<int>(result.status);
}

extern "C" void stickslip_node_on_frame(const stickslip::can::Frame* frame) {
  if (frame->id != kNodeInputId || frame->length < 2 || (frame->flags & stickslip::can::kRemote))
    return;
  const auto raw = static_cast<std::int16_t>(static_cast<std::uint16_t>(
      frame->data[0] | static_cast<unsigned>(frame->data[1]) << 8));
  const Scalar a_u = Scalar(static_cast<int>(raw)) * kPerMilli;
  const stickslip::StepOutput<Scalar> out = seat.step(a_u);
  last_output = out;

  static stickslip::can::Frame reply;  // statically allocated: not on the interrupt's stack
  reply.id = kNodeOutputId;
  reply.length = 5;
  const auto a_x = static_cast<std::uint16_t>(to_milli(out.a_x_m_per_s2));
  reply.data[0] = static_cast<std::uint8_t>(a_x & 0xffu);
  reply.data[1] = static_cast<std::uint8_t>(a_x >> 8);
  reply.data[2] = out.stuck ? 1u : 0u;
  reply.data[3] = out.events;
  reply.data[4] = seat.saturated_steps() != 0 ? 1u : 0u;
  board_can_send(&reply);
}

namespace {

std::uint64_t bits_of(Scalar v) {
#if defined(STICKSLIP_FIRMWARE_FIXED)
  return static_cast<std::uint64_t>(v.raw());
#else
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  return bits;
#endif
}

}  // namespace

extern "C" void stickslip_node_record(std::uint8_t* out) {
  const Scalar fields[6] = {last_output.x_r_m,      last_output.v_r_m_per_s,
                            last_output.a_x_m_per_s2, last_output.friction_n,
                            last_output.stuck_time_s, last_output.stuck_fraction};
  for (const Scalar field : fields) {
    const std::uint64_t bits = bits_of(field);
    for (int byte = 0; byte < 8; ++byte) *out++ = static_cast<std::uint8_t>(bits >> (8 * byte));
  }
  *out++ = last_output.stuck ? 1u : 0u;
  *out++ = last_output.events;
  *out = seat.saturated_steps() != 0 ? 1u : 0u;
}

// The CAN controller's receive interrupt (IRQ 0 in startup.cpp's vector table).
extern "C" void CAN0_IRQHandler() {
  stickslip::can::Frame frame;
  while (board_can_read(&frame)) stickslip_node_on_frame(&frame);
}

// Called by Reset_Handler (startup.cpp).
extern "C" void firmware_main() {
  if (stickslip_node_start() == 0) board_start();
  for (;;) board_idle();
}
