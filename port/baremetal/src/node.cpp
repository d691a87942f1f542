#include "node.hpp"

#include <cstring>
#include <type_traits>

#include "board.hpp"
#include "stickslip/can/ecu_node.hpp"
#include "stickslip/can/node_seats.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/scaled_end_stops.hpp"

namespace {

// STICKSLIP_FIRMWARE_END_STOPS: the seat of docs/scenes/seat-with-end-stops.toml, its stroke
// limited by stiff, damped end stops (models/end_stops.hpp), as the host node runs that scene;
// otherwise the reference seat without stops.
#if defined(STICKSLIP_FIRMWARE_END_STOPS)
constexpr bool kEndStops = true;
#else
constexpr bool kEndStops = false;
#endif

#if defined(STICKSLIP_FIRMWARE_FIXED)
// Cortex-M0+ (no FPU, 32-bit multiply only): Q7.24 in scene units (models/scaled_oscillator.hpp,
// models/scaled_end_stops.hpp).
using Scalar = stickslip::Fixed32;
using Seat =
    std::conditional_t<kEndStops,
                       stickslip::can::ScaledSeat<
                           Scalar, stickslip::CoulombStickSlip,
                           stickslip::ScaledEndStopOscillator<Scalar, stickslip::CoulombStickSlip>>,
                       stickslip::can::ScaledSeat<Scalar, stickslip::CoulombStickSlip>>;
template <typename S>
const auto& model_of(const S& s) {
  return s.model().oscillator();
}
// Its statistics: the block window over its own words (can/word_window.hpp), in integers, one
// division or square root per sample in the samples after a block completes.
#else
using Scalar = float;  // Cortex-M4F: single-precision FPU
// The observer, as the host node runs it: its estimate is the model's step, and its window
// gives SeatStats and SeatScene (T_ax, p, K; figured in float once per block).
using Seat = stickslip::can::ObserverSeat<Scalar, stickslip::CoulombStickSlip, kEndStops>;
template <typename S>
const auto& model_of(const S& s) {
  return s.oscillator();
}
#endif
// The event search this build's bound on the work of one step takes
// (port/baremetal/loop-bounds.json, tools/elf-wcet.py): ticks of dt / 2^kSeatEventLevel, a Taylor
// polynomial of order at most kSeatTaylorOrder (the reference seat's in float; Q7.24 solves its
// cubic over the whole step). stickslip_node_start() refuses a seat that needs a finer search (a
// stiffer seat or a longer dt), which would run past the bound.
constexpr int kSeatEventLevel = 0;
constexpr int kSeatTaylorOrder = 3;
// The end-stop seat's event loop runs its event budget and one pass more; the bounds file takes
// that budget as kMaxEndStopEventsOfTheExactSolutionPerStep + 1 (Coulomb stick-slip's).
static_assert(stickslip::EndStopOscillator<Scalar, stickslip::CoulombStickSlip>::kEventBudget ==
              stickslip::kMaxEndStopEventsOfTheExactSolutionPerStep + 1);
// Every sample SeatMotion and SeatForce, every tenth SeatStats and SeatScene (as the host node's
// --outputs full).
constexpr stickslip::can::OutputSet kOutputs = stickslip::can::OutputSet::full;

Seat seat;  // the model's coefficients and state, statically allocated (no heap)

}  // namespace

// The model's step alone, on the static seat: the step budget of the Cortex-M0+ (code and stack,
// tools/check-embedded.sh) is measured from here; the node around it is reported apart.
extern "C" __attribute__((noinline)) void stickslip_seat_step(Scalar a_u) {
  seat.advance(a_u);
}

namespace {

// The seat as the lib node sees it: the static seat, its step through stickslip_seat_step().
struct FirmwareSeat {
  stickslip::can::SeatWords start(std::uint16_t a_u_word) { return seat.start(a_u_word); }
  stickslip::can::SeatWords step(std::uint16_t a_u_word) {
    stickslip_seat_step(seat.input(a_u_word));
    return seat.finish_step(a_u_word);
  }
  stickslip::can::StatsWords statistics() const { return seat.statistics(); }
};

stickslip::can::EcuNode<FirmwareSeat> node;  // the receive checker, statically allocated

// The node's output goes to the board's CAN driver.
struct BoardSink {
  void send(const stickslip::can::Frame& frame) { board_can_send(&frame); }
  void sampled(const stickslip::can::NodeSample& /*sample*/) { board_node_sampled(); }
};

// The scene's seat on the static seat: the end stops only where this build's seat has them.
template <typename S>
stickslip::ConfigResult configure_seat(S& s, const stickslip::OscillatorParams& params,
                                       const stickslip::EndStopParams& stops) {
#if defined(STICKSLIP_FIRMWARE_FIXED)
  if constexpr (kEndStops) {
    return s.configure(params, stops);
  } else {
    return s.configure(params);
  }
#else
  stickslip::ObserverParams observer = stickslip::can::seat_observer_params(params);
  if constexpr (kEndStops) observer.stops = stops;
  return s.configure(observer);
#endif
}

}  // namespace

extern "C" int stickslip_node_start() {
  stickslip::OscillatorParams params;  // the reference seat (with end stops: the scene's friction)
  params.model = stickslip::FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = kEndStops ? 30.0 : 45.0;
  params.dt_s = 1e-3;
  params.integrator = stickslip::Integrator::exact;
  // The ranges the fixed-point scaling must hold: the SeatInput a_u signal (+-32 m/s^2), the
  // seat's stroke.
  params.input_range_m_per_s2 = 32.768;
  params.displacement_range_m = 0.1;
  stickslip::EndStopParams stops;  // docs/scenes/seat-with-end-stops.toml
  stops.travel_m = 0.05;
  stops.stiffness_n_per_m = 2.0e5;
  stops.damping_ns_per_m = 2.0e3;
  const stickslip::ConfigResult result = configure_seat(seat, params, stops);
  if (!result.ok()) return static_cast<int>(result.status);
  // The seat with end stops scans its step on its engine's fixed grid (models/end_stops.hpp, whose
  // trip counts port/baremetal/loop-bounds.json takes from its constants), so only the plain
  // seat's tick level is bounded here; the order of the Taylor polynomials is bounded for both.
  const stickslip::EventSearchPlan plan = model_of(seat).event_search();
  if (plan.taylor_order > kSeatTaylorOrder || (!kEndStops && plan.tick_level > kSeatEventLevel))
    return static_cast<int>(stickslip::Status::unsupported);
  stickslip::can::EcuNodeParams node_params;
  node_params.outputs = kOutputs;
  return static_cast<int>(node.configure(node_params));
}

extern "C" void stickslip_node_on_frame(const stickslip::can::Frame* frame) {
  BoardSink sink;
  // No clock on the example board: the silence timeout (a host feature) is not used.
  node.on_frame(*frame, 0, sink);
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
  const stickslip::StepOutput<Scalar>& last = seat.last();
  const Scalar fields[6] = {last.x_r_m,      last.v_r_m_per_s,  last.a_x_m_per_s2,
                            last.friction_n, last.stuck_time_s, last.stuck_fraction};
  for (const Scalar field : fields) {
    const std::uint64_t bits = bits_of(field);
    for (int byte = 0; byte < 8; ++byte) *out++ = static_cast<std::uint8_t>(bits >> (8 * byte));
  }
  *out++ = last.stuck ? 1u : 0u;
  *out++ = last.events;
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
