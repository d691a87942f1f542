// Den Hartog's harmonic balance (harmonic_balance.hpp) against closed forms and the simulated
// steady state: exact in the linear limit, close for small K, invalid from K = 1.
#include <cmath>
#include <string>

#include "stickslip/host/run/harmonic_balance.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAmplitude = 0.35 * 1.4142135623730951;  // a0u = 0.35 m/s^2

OscillatorParams seat(double damping, double k_value, double amplitude = kAmplitude) {
  OscillatorParams p;  // m = 88.4 kg, k = 11.5 kN/m
  p.damping_ns_per_m = damping;
  p.kinetic_friction_n = p.static_friction_n = k_value * kPi * p.mass_kg * amplitude / 4.0;
  p.model = FrictionModel::stick_slip;
  p.integrator = Integrator::exact;
  p.dt_s = 1e-3;
  return p;
}

}  // namespace

TEST_GROUP(HarmonicBalance){};

TEST(HarmonicBalance, LinearLimitIsTheLinearAmplitudeExactly) {
  for (double b : {0.0, 100.0, 504.0, 3000.0}) {
    for (double f : {0.5, 1.5, 2.5, 6.0}) {
      const OscillatorParams p = seat(b, 0.0);
      const HarmonicBalance hb = den_hartog_harmonic_balance(p, kAmplitude, f);
      const double w = 2.0 * kPi * f;
      const double linear =
          p.mass_kg * kAmplitude / std::hypot(p.stiffness_n_per_m - p.mass_kg * w * w, b * w);
      CHECK_TRUE(hb.valid);
      DOUBLES_EQUAL(linear, hb.amplitude_m, 1e-15 * linear);
    }
  }
  // ... and the simulated linear steady state.
  OscillatorParams p = seat(504.0, 0.0);
  p.model = FrictionModel::linear;
  const SteadyState sim = simulate_harmonic_steady_state(p, kAmplitude, 1.5, 40.0);
  const double hb = den_hartog_harmonic_balance(p, kAmplitude, 1.5).amplitude_m;
  DOUBLES_EQUAL(hb, sim.amplitude_m, 1e-4 * hb);
}

TEST(HarmonicBalance, UndampedCaseIsDenHartogsClosedForm) {
  for (double k_value : {0.1, 0.5, 0.9}) {
    for (double f : {0.8, 3.0}) {
      const OscillatorParams p = seat(0.0, k_value);
      const double w = 2.0 * kPi * f;
      const double expected = p.mass_kg * kAmplitude /
                              std::fabs(p.stiffness_n_per_m - p.mass_kg * w * w) *
                              std::sqrt(1.0 - k_value * k_value);
      const HarmonicBalance hb = den_hartog_harmonic_balance(p, kAmplitude, f);
      DOUBLES_EQUAL(k_value, hb.k, 1e-12);
      DOUBLES_EQUAL(expected, hb.amplitude_m, 1e-12 * expected);
    }
  }
}

// With b = 504 N s/m at 1.5 Hz: within 1 % of the simulated steady state up to K = 0.3, the
// amplitude falls with K, and the error grows as K approaches 1 (the mass starts to stick).
TEST(HarmonicBalance, AgreesWithSimulationForSmallKAndFailsTowardsKOne) {
  double previous = 1.0;
  for (double k_value : {0.05, 0.1, 0.2, 0.3}) {
    const OscillatorParams p = seat(504.0, k_value);
    const HarmonicBalance hb = den_hartog_harmonic_balance(p, kAmplitude, 1.5);
    const SteadyState sim = simulate_harmonic_steady_state(p, kAmplitude, 1.5, 40.0);
    CHECK_TRUE(hb.valid);
    DOUBLES_EQUAL(sim.amplitude_m, hb.amplitude_m, 0.01 * sim.amplitude_m);
    DOUBLES_EQUAL(0.0, sim.stick_probability, 1e-12);
    CHECK_TRUE(hb.amplitude_m < previous);
    previous = hb.amplitude_m;
  }
  const OscillatorParams near_one = seat(504.0, 0.9);
  const HarmonicBalance hb = den_hartog_harmonic_balance(near_one, kAmplitude, 1.5);
  const SteadyState sim = simulate_harmonic_steady_state(near_one, kAmplitude, 1.5, 40.0);
  CHECK_TRUE(hb.valid);
  CHECK_TRUE(std::fabs(hb.amplitude_m / sim.amplitude_m - 1.0) > 0.2);
  CHECK_TRUE(sim.stick_probability > 0.1);
  for (double k_value : {1.0, 1.2}) {
    const OscillatorParams p = seat(504.0, k_value);
    CHECK_FALSE(den_hartog_harmonic_balance(p, kAmplitude, 1.5).valid);
    CHECK_TRUE(simulate_harmonic_steady_state(p, kAmplitude, 1.5, 40.0).stick_probability > 0.3);
  }
}
