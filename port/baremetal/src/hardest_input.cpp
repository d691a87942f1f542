// Writes the hardest input set for the firmware's instruction count (tools/qemu-worst-case.sh):
// an a_u recording (CSV t,a_u in m/s^2, whole words of 2^-10 m/s^2 as SeatInput carries them)
// that keeps the reference seat at its break-away threshold as often as it can, so that steps
// with events (break-away, stick, reversal, several in one step) and slips that come to rest
// inside a step are as frequent as the physics allows, mixed with full-range jumps (slips at the
// largest accelerations the signal holds) and swings about the holding point.
//   stickslip_node_hardest_input SECONDS OUTPUT.csv
// The input is chosen sample by sample from the state of a double seat with the firmware's
// parameters (port/baremetal/src/node.cpp), in a cycle of 4 s:
//   - second 0, full-range jumps;
//   - seconds 1 and 3, at the threshold: a_u such that the limit force -(m a_u + k x_r) lands on
//     +F_fs or -F_fs (alternating every 7 samples) plus an offset of random size and sign;
//   - second 2, swings: the limit force uniform within +-s F_fs about 0, s = 1.5, 3, 6 or 10 by
//     cycle (the Cortex-M4F's slowest frames come from these: a break-away, a slip and a stick
//     in one step, from any starting force).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

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

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || !(std::atof(argv[1]) > 0.0)) {
    std::fprintf(stderr, "usage: %s SECONDS OUTPUT.csv\n", argv[0]);
    return 2;
  }
  stickslip::OscillatorParams params;  // the firmware's seat (node.cpp)
  params.model = stickslip::FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = 45.0;
  params.dt_s = 1e-3;
  params.integrator = stickslip::Integrator::exact;
  stickslip::Oscillator<double, stickslip::CoulombStickSlip> seat;
  if (!seat.configure(params).ok()) return 1;
  std::FILE* out = std::fopen(argv[2], "w");
  if (out == nullptr) {
    std::fprintf(stderr, "stickslip_node_hardest_input: cannot write %s\n", argv[2]);
    return 1;
  }
  const auto samples = static_cast<long>(std::atof(argv[1]) / params.dt_s) + 1;
  Xorshift random;
  std::fprintf(out, "t,a_u\n");
  for (long n = 0; n < samples; ++n) {
    double a_u = 0.0;
    const long second = n / 1000;
    const double holding = -params.stiffness_n_per_m * seat.x_r() / params.mass_kg;
    if (second % 4 == 0) {
      a_u = 30.0 * random.uniform();  // full-range jumps: slipping, reversals
    } else if (second % 4 == 2) {
      const double swing = kSwings[(second / 4) % 4];
      a_u = holding + swing * params.static_friction_n / params.mass_kg * random.uniform();
    } else {
      const double side = (n / 7) % 2 == 0 ? 1.0 : -1.0;
      const double offset = random.uniform() * std::pow(10.0, -3.0 * std::fabs(random.uniform()));
      a_u = holding - side * params.static_friction_n / params.mass_kg + offset;
    }
    long word = std::lround(a_u / kWord_m_per_s2);
    word = word > kLargestWord ? kLargestWord : (word < -kLargestWord ? -kLargestWord : word);
    const double sent = static_cast<double>(word) * kWord_m_per_s2;  // exact in decimal too
    seat.step(sent);
    std::fprintf(out, "%.3f,%.10f\n", static_cast<double>(n) * params.dt_s, sent);
  }
  return std::fclose(out) == 0 ? 0 : 1;
}
