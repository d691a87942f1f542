#include "node.hpp"

#include <cstring>

#include "board.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_oscillator.hpp"

namespace {

#if defined(STICKSLIP_FIRMWARE_FIXED)
// Cortex-M0+ (no FPU, 32-bit multiply only): Q7.24 in scene units (models/scaled_oscillator.hpp).
using Scalar = stickslip::Fixed32;
using Seat = stickslip::ScaledOscillator<Scalar, stickslip::CoulombStickSlip>;
stickslip::CountScale<Scalar> input_scale;   // mm/s^2 -> scene units
stickslip::CountScale<Scalar> output_scale;  // scene units -> mm/s^2
const stickslip::Oscillator<Scalar, stickslip::CoulombStickSlip>& model_of(const Seat& s) {
  return s.oscillator();
}
#else
using Scalar = float;  // Cortex-M4F: single-precision FPU
using Seat = stickslip::Oscillator<Scalar, stickslip::CoulombStickSlip>;
const Seat& model_of(const Seat& s) {
  return s;
}
#endif

Seat seat;  // the model's coefficients and state, statically allocated (no heap)
stickslip::StepOutput<Scalar> last_output{};

constexpr std::int32_t kMilliLimit = 32767;  // int16 mm/s^2

// The CAN payload's a_u (mm/s^2) as the model's input.
Scalar input_of(std::int16_t milli) {
#if defined(STICKSLIP_FIRMWARE_FIXED)
  return input_scale.to_scalar(milli);
#else
  return static_cast<float>(milli) * 0.001f;
#endif
}

// The model's a_x in mm/s^2, rounded to nearest and clamped to int16.
std::int16_t to_milli(Scalar v) {
#if defined(STICKSLIP_FIRMWARE_FIXED)
  return static_cast<std::int16_t>(output_scale.to_count(v, kMilliLimit));
#else
  const float scaled = v * 1000.0f;
  const float limit = static_cast<float>(kMilliLimit);
  const float clamped = scaled > limit ? limit : (scaled < -limit ? -limit : scaled);
  return static_cast<std::int16_t>(clamped + (clamped < 0.0f ? -0.5f : 0.5f));
#endif
}

}  // namespace

extern "C" int stickslip_node_start() {
  stickslip::OscillatorParams params;  // the reference seat
  params.model = stickslip::FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = 45.0;
  params.dt_s = 1e-3;
  params.integrator = stickslip::Integrator::exact;
  // The ranges the fixed-point scaling must hold: the int16 mm/s^2 input, the seat's stroke.
  params.input_range_m_per_s2 = 32.768;
  params.displacement_range_m = 0.1;
  const stickslip::ConfigResult result = seat.configure(params);
#if defined(STICKSLIP_FIRMWARE_FIXED)
  if (result.ok()) {
    const double unit = seat.units().acceleration_m_per_s2();
    if (!input_scale.set_count_to_scalar(1e-3 / unit) ||
        !output_scale.set_scalar_to_count(unit / 1e-3))
      return static_cast<int>(stickslip::Status::out_of_range);
  }
#endif
  return static_cast<int>(result.status);
}

extern "C" void stickslip_node_on_frame(const stickslip::can::Frame* frame) {
  if (frame->id != kNodeInputId || frame->length < 2 || (frame->flags & stickslip::can::kRemote))
    return;
  const auto raw = static_cast<std::int16_t>(
      static_cast<std::uint16_t>(frame->data[0] | static_cast<unsigned>(frame->data[1]) << 8));
  const Scalar a_u = input_of(raw);
  seat.step(a_u, last_output);  // in place: no copy of the outputs on the interrupt's stack
  const stickslip::StepOutput<Scalar>& out = last_output;

  static stickslip::can::Frame reply;  // statically allocated: not on the interrupt's stack
  reply.id = kNodeOutputId;
  reply.length = 5;
  const auto a_x = static_cast<std::uint16_t>(to_milli(out.a_x_m_per_s2));
  reply.data[0] = static_cast<std::uint8_t>(a_x & 0xffu);
  reply.data[1] = static_cast<std::uint8_t>(a_x >> 8);
  reply.data[2] = out.stuck ? 1u : 0u;
  reply.data[3] = out.events;
  reply.data[4] = model_of(seat).saturated_steps() != 0 ? 1u : 0u;
  board_can_send(&reply);
}

namespace {

std::uint64_t bits_of(Scalar v) {
#if defined(STICKSLIP_FIRMWARE_FIXED)
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(v.raw()));
#else
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  return bits;
#endif
}

}  // namespace

extern "C" void stickslip_node_record(std::uint8_t* out) {
  const Scalar fields[6] = {last_output.x_r_m,        last_output.v_r_m_per_s,
                            last_output.a_x_m_per_s2, last_output.friction_n,
                            last_output.stuck_time_s, last_output.stuck_fraction};
  for (const Scalar field : fields) {
    const std::uint64_t bits = bits_of(field);
    for (int byte = 0; byte < 8; ++byte) *out++ = static_cast<std::uint8_t>(bits >> (8 * byte));
  }
  *out++ = last_output.stuck ? 1u : 0u;
  *out++ = last_output.events;
  *out = model_of(seat).saturated_steps() != 0 ? 1u : 0u;
}

// The CAN controller's receive interrupt (IRQ 0 in startup.cpp's vector table).
extern "C" void CAN0_IRQHandler() {
  // Static: the 80-byte CAN FD frame stays off the interrupt's stack (the handler does not nest).
  static stickslip::can::Frame frame;
  while (board_can_read(&frame)) stickslip_node_on_frame(&frame);
}

// Called by Reset_Handler (startup.cpp).
extern "C" void firmware_main() {
  if (stickslip_node_start() == 0) board_start();
  for (;;) board_idle();
}
