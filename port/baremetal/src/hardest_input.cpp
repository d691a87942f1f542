// Writes the hardest input set for the firmware's instruction count (tools/qemu-worst-case.sh):
// an a_u recording (CSV t,a_u in m/s^2, whole words of 2^-10 m/s^2 as SeatInput carries them)
// that keeps the seat at its break-away threshold as often as it can, so that steps with events
// (break-away, stick, reversal, several in one step) and slips that come to rest inside a step
// are as frequent as the physics allows, mixed with full-range jumps (slips at the largest
// accelerations the signal holds) and swings about the holding point.
//   stickslip_node_hardest_input SECONDS OUTPUT.csv [--end-stops]
// The input is chosen sample by sample from the state of a double seat with the firmware's
// parameters (port/baremetal/src/node.cpp), in a cycle of 4 s:
//   - second 0, full-range jumps;
//   - seconds 1 and 3, at the threshold: a_u such that the limit force -(m a_u + k x_r) lands on
//     +F_fs or -F_fs (alternating every 7 samples) plus an offset of random size and sign;
//   - second 2, swings: the limit force uniform within +-s F_fs about 0, s = 1.5, 3, 6 or 10 by
//     cycle (the Cortex-M4F's slowest frames come from these: a break-away, a slip and a stick
//     in one step, from any starting force).
// --end-stops: the seat of docs/scenes/seat-with-end-stops.toml (the firmware built with
// STICKSLIP_FIRMWARE_END_STOPS), whose limit force holds the stop's force as well, and second 1
// drives it to a stop instead (the side alternating by cycle): a_u that would bring x_r to the
// stop's edge, within +-2 mm at random, with a random force of up to 2 F_fs, so that the seat
// meets, leaves, sticks at and breaks away from the stop in the same steps; seconds 2 and 3 then
// start where it was left, at the stop.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

struct Xorshift {  // deterministic: the same file on every machine
  std::uint64_t state = 0x9e3779b97f4a7c15u;
  double uniform() {  // in [-1, 1)
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) / 4503599627370496.0 - 1.0;
  }
};

constexpr double kWord_m_per_s2 = 1.0 / 1024.0;       // SeatInput.a_u (docs/can/stickslip.dbc)
constexpr long kLargestWord = 32767;                  // its int16 range
constexpr double kSwings[4] = {1.5, 3.0, 6.0, 10.0};  // limit-force swings, in F_fs

// The seat of node.cpp, with or without its stops, behind one interface.
template <typename Seat>
struct HardestInput {
  Seat seat;
  stickslip::OscillatorParams params;
  double stop_force_n() const {
    if constexpr (std::is_same_v<Seat, stickslip::Oscillator<double, stickslip::CoulombStickSlip>>)
      return 0.0;
    else
      return seat.stop_force_n();
  }
};

// a_u for sample n, from the seat's state.
template <typename Source>
double next_a_u(const Source& in, long n, bool end_stops, Xorshift& random) {
  const stickslip::OscillatorParams& p = in.params;
  const long second = n / 1000;
  const double fs_per_kg = p.static_friction_n / p.mass_kg;
  // The floor acceleration at which the seat, held, needs no friction: the spring's and the stop's
  // force balanced by the floor's.
  const double holding = -(p.stiffness_n_per_m * in.seat.x_r() + in.stop_force_n()) / p.mass_kg;
  if (second % 4 == 0) return 30.0 * random.uniform();  // full-range jumps: slipping, reversals
  if (second % 4 == 1 && end_stops) {
    // x_r'' = -a_u - (k x_r + b v_r + F_stop + F_f) / m: a_u asks for a critically damped approach
    // (10 Hz) to the stop's edge, the friction left out and a random force put in its place.
    const double side = (second / 4) % 2 == 0 ? 1.0 : -1.0;
    const double target = side * (0.05 + 0.002 * random.uniform());
    const double omega = 2.0 * 3.141592653589793 * 10.0;
    const double wanted = -omega * omega * (in.seat.x_r() - target) - 2.0 * omega * in.seat.v_r();
    return -wanted + holding - p.damping_ns_per_m * in.seat.v_r() / p.mass_kg +
           2.0 * fs_per_kg * random.uniform();
  }
  if (second % 4 == 2) {
    const double swing = kSwings[(second / 4) % 4];
    return holding + swing * p.static_friction_n / p.mass_kg * random.uniform();
  }
  const double side = (n / 7) % 2 == 0 ? 1.0 : -1.0;
  const double offset = random.uniform() * std::pow(10.0, -3.0 * std::fabs(random.uniform()));
  return holding - side * fs_per_kg + offset;
}

template <typename Source>
int write(Source& in, bool end_stops, double seconds, std::FILE* out) {
  const auto samples = static_cast<long>(seconds / in.params.dt_s) + 1;
  Xorshift random;
  std::fprintf(out, "t,a_u\n");
  for (long n = 0; n < samples; ++n) {
    long word = std::lround(next_a_u(in, n, end_stops, random) / kWord_m_per_s2);
    word = word > kLargestWord ? kLargestWord : (word < -kLargestWord ? -kLargestWord : word);
    const double sent = static_cast<double>(word) * kWord_m_per_s2;  // exact in decimal too
    in.seat.step(sent);
    std::fprintf(out, "%.3f,%.10f\n", static_cast<double>(n) * in.params.dt_s, sent);
  }
  return std::fclose(out) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const bool end_stops = argc == 4 && std::strcmp(argv[3], "--end-stops") == 0;
  if ((argc != 3 && !end_stops) || !(std::atof(argv[1]) > 0.0)) {
    std::fprintf(stderr, "usage: %s SECONDS OUTPUT.csv [--end-stops]\n", argv[0]);
    return 2;
  }
  stickslip::OscillatorParams params;  // the firmware's seat (node.cpp)
  params.model = stickslip::FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = end_stops ? 30.0 : 45.0;
  params.dt_s = 1e-3;
  params.integrator = stickslip::Integrator::exact;
  stickslip::EndStopParams stops;  // docs/scenes/seat-with-end-stops.toml
  stops.travel_m = 0.05;
  stops.stiffness_n_per_m = 2.0e5;
  stops.damping_ns_per_m = 2.0e3;
  HardestInput<stickslip::Oscillator<double, stickslip::CoulombStickSlip>> plain;
  HardestInput<stickslip::EndStopOscillator<double, stickslip::CoulombStickSlip>> stopped;
  plain.params = stopped.params = params;
  if (!(end_stops ? stopped.seat.configure(params, stops) : plain.seat.configure(params)).ok()) {
    std::fprintf(stderr, "stickslip_node_hardest_input: the firmware's seat does not configure\n");
    return 1;
  }
  std::FILE* out = std::fopen(argv[2], "w");
  if (out == nullptr) {
    std::fprintf(stderr, "stickslip_node_hardest_input: cannot write %s\n", argv[2]);
    return 1;
  }
  const double seconds = std::atof(argv[1]);
  return end_stops ? write(stopped, true, seconds, out) : write(plain, false, seconds, out);
}
