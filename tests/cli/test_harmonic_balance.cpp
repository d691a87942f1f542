// Den Hartog's harmonic balance: exact in its limits, close to the simulated steady state while the
// seat keeps slipping (small K), and declared invalid from K = 1 on, where the seat sticks.
#include <cmath>
#include <cstddef>

#include "CppUTest/TestHarness.h"
#include "stickslip/friction/laws.hpp"
#include "stickslip/host/harmonic_balance.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;
using stickslip::host::harmonic_balance;
using stickslip::host::HarmonicBalance;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMass = 88.4, kStiffness = 11500.0;

struct SteadyState {
  double amplitude_m;
  double stuck_share;
};

// Exact stick-slip simulation of a_u = A sin(w t) for 40 s; amplitude of x_r over the last 10 s.
SteadyState simulate(double damping, double friction_n, double amplitude, double frequency_hz) {
  OscillatorParams p;
  p.mass_kg = kMass;
  p.stiffness_n_per_m = kStiffness;
  p.damping_ns_per_m = damping;
  p.kinetic_friction_n = p.static_friction_n = friction_n;
  p.model = FrictionModel::stick_slip;
  p.integrator = Integrator::exact;
  p.dt_s = 1e-3;
  Oscillator<double, CoulombStickSlip> seat;
  CHECK_TRUE(seat.configure(p).ok());
  seat.reset(0.0, 0.0, 0.0);
  double low = 0.0, high = 0.0, stuck = 0.0;
  const std::size_t steps = 40000, settled = 30000;
  for (std::size_t n = 1; n <= steps; ++n) {
    const double t = static_cast<double>(n) * p.dt_s;
    const StepOutput<double> out = seat.step(amplitude * std::sin(2 * kPi * frequency_hz * t));
    if (n > settled) {
      low = std::fmin(low, out.x_r_m);
      high = std::fmax(high, out.x_r_m);
      stuck += out.stuck_fraction;
    }
  }
  return {(high - low) / 2, stuck / static_cast<double>(steps - settled)};
}

double friction_for_k(double k, double amplitude) { return k * kPi * kMass * amplitude / 4.0; }

}  // namespace

TEST_GROUP(HarmonicBalance){};

// Without friction it is the linear frequency response of x_r; without damping, Den Hartog's
// closed form X = m A sqrt(1 - K^2) / |k - m w^2|.
TEST(HarmonicBalance, ReducesToTheClosedFormsInItsLimits) {
  const double a = 0.5, f = 1.3, w = 2 * kPi * f;
  const HarmonicBalance linear = harmonic_balance(kMass, kStiffness, 504.0, 0.0, a, f);
  CHECK_TRUE(linear.valid);
  const double linear_x = kMass * a / std::hypot(kStiffness - kMass * w * w, 504.0 * w);
  DOUBLES_EQUAL(linear_x, linear.relative_amplitude_m, 1e-15);
  const double friction = friction_for_k(0.6, a);
  const HarmonicBalance undamped = harmonic_balance(kMass, kStiffness, 0.0, friction, a, f);
  CHECK_TRUE(undamped.valid);
  DOUBLES_EQUAL(0.6, undamped.den_hartog_k, 1e-14);
  const double closed = kMass * a * std::sqrt(1 - 0.36) / std::fabs(kStiffness - kMass * w * w);
  DOUBLES_EQUAL(closed, undamped.relative_amplitude_m, 1e-14 * closed);
}

// While the seat slips all the time (K well below 1) the simulated steady state follows the
// harmonic balance, which underestimates X more as K grows (measured at 1 Hz, A = 0.5 m/s^2:
// K = 0.1: -0.5 %; K = 0.3: -2.1 % with b = 504 N s/m, -4.2 % undamped).
TEST(HarmonicBalance, FollowsTheSimulatedSteadyStateWhileTheSeatSlips) {
  const double a = 0.5, f = 1.0;
  for (const double damping : {504.0, 0.0}) {
    for (const double k : {0.1, 0.3}) {
      const double friction = friction_for_k(k, a);
      const HarmonicBalance hb = harmonic_balance(kMass, kStiffness, damping, friction, a, f);
      const SteadyState sim = simulate(damping, friction, a, f);
      CHECK_TRUE(hb.valid);
      DOUBLES_EQUAL(0.0, sim.stuck_share, 1e-3);
      DOUBLES_EQUAL(hb.relative_amplitude_m, sim.amplitude_m, (k < 0.2 ? 0.01 : 0.05) * sim.amplitude_m);
    }
  }
}

// From K = 1 on the method has no solution, and the simulated seat sticks for part of each cycle.
TEST(HarmonicBalance, IsInvalidFromKOneOnWhereTheSeatSticks) {
  const double a = 0.5, f = 1.0;
  for (const double k : {1.0, 1.5}) {
    const double friction = friction_for_k(k, a);
    CHECK_FALSE(harmonic_balance(kMass, kStiffness, 504.0, friction, a, f).valid);
    CHECK_TRUE(simulate(504.0, friction, a, f).stuck_share > 0.2);
  }
  CHECK_TRUE(harmonic_balance(kMass, kStiffness, 504.0, friction_for_k(0.95, a), a, f).valid);
}
