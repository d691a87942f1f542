// The actuator force f_a held over each sample interval: the reference solver's path
// (solve_reference_actuated) against a closed form and a refinement in dt, then the core's
// simulate with that force against the reference.
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u + f_a,   F_L = f_a - (m a_u + k x_r).
// The closed forms come from tests/core/oracles.hpp, which never calls a solver.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "../core/oracles.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/run/simulation.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

constexpr double kMass = test::kMassKg;
constexpr double kStiffness = test::kStiffnessNPerM;

OscillatorParams seat(FrictionModel model, double dt_s, double kinetic_n, double static_n) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, dt_s);
  p.kinetic_friction_n = kinetic_n;
  p.static_friction_n = static_n;
  return p;
}

// A force that changes at every sample (a sampled sum of two sines) plus steps every 37 samples:
// what a controller's output stage holds.
std::vector<double> actuator_force(std::size_t count, double dt_s, double amplitude_n) {
  std::vector<double> f(count);
  test::SplitMix64 random(3);
  double level = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    const double t = static_cast<double>(n) * dt_s;
    if (n % 37 == 0) level = random.uniform(-amplitude_n, amplitude_n);
    f[n] = level + 0.5 * amplitude_n * std::sin(2.0 * test::kPi * 1.3 * t) +
           0.2 * amplitude_n * std::sin(2.0 * test::kPi * 7.1 * t + 0.4);
  }
  return f;
}

double relative_rms(const std::vector<double>& value, const std::vector<double>& oracle) {
  double error = 0.0, norm = 0.0;
  for (std::size_t n = 0; n < oracle.size(); ++n) {
    error += (value[n] - oracle[n]) * (value[n] - oracle[n]);
    norm += oracle[n] * oracle[n];
  }
  return std::sqrt(error / norm);
}

}  // namespace

TEST_GROUP(ActuatedReference){};

// A constant force F on a seat whose floor is at rest is a constant base acceleration -F/m:
// the seat follows the chain of damped half cycles about (F -+ F_fk)/k, to 1e-12 m at every
// sample (the closed form's own accuracy, as for the base acceleration itself), and stops there.
TEST(ActuatedReference, AConstantForceFollowsTheHalfCycleChainOfTheFreeDecay) {
  const double dt = 1e-3;
  for (double force : {150.0, -180.0, 400.0}) {
    const auto chain = test::coulomb_half_cycles(kMass, kStiffness, test::kDampingNsPerM, 40.0,
                                                 50.0, -force / kMass, 0.0);
    CHECK(chain.sticks);
    const std::size_t count = 3001;
    const std::vector<double> a_u(count, 0.0), f_a(count, force);
    const ReferenceTrace trace =
        solve_reference_actuated(seat(FrictionModel::stick_slip, dt, 40.0, 50.0), a_u, f_a);
    double worst = 0.0;
    for (std::size_t n = 0; n < count; ++n) {
      double x = 0.0, v = 0.0;
      chain.state_at(static_cast<double>(n) * dt, x, v);
      worst = std::max(worst, std::fabs(trace.x_r_m[n] - x));
    }
    CHECK(worst < 1e-12);
    LONGS_EQUAL(chain.count, static_cast<long>(trace.events));
    // Held at the end: a_x = a_u = 0 exactly, the friction holds F_L = F - k x_r.
    CHECK_EQUAL(1, trace.stuck[count - 1]);
    CHECK_EQUAL(0.0, trace.a_x_m_per_s2[count - 1]);
    DOUBLES_EQUAL(force - kStiffness * trace.x_r_m[count - 1], trace.friction_n[count - 1],
                  1e-12 * std::fabs(force));
    test::note_margin("actuated reference vs half-cycle chain, m", worst, 1e-12);
  }
}

// The hold: a force held over a coarse interval is the same force held over each of its 50 fine
// intervals, with the same first-order-hold a_u(t). At the common instants the two runs agree to
// 1e-12 of the motion's scale, with the same events (the coarse run finds them inside its
// intervals).
TEST(ActuatedReference, CoarseHoldMatchesTheSameForceOnAFinerGrid) {
  const double dt = 0.02;
  const std::size_t ratio = 50, count = 1001;  // 20 s
  const std::vector<double> coarse = test::make_lorry_signal(5, 1.2).sample(dt, count);
  const std::vector<double> force = actuator_force(count, dt, 60.0);
  std::vector<double> fine((count - 1) * ratio + 1), fine_force(fine.size());
  for (std::size_t j = 0; j < fine.size(); ++j) {
    fine[j] = test::refine_linear(coarse, j, ratio);
    fine_force[j] = force[(j + ratio - 1) / ratio];  // interval j lies in coarse interval ceil(j/r)
  }
  const OscillatorParams pc = seat(FrictionModel::stick_slip, dt, 40.0, 50.0);
  OscillatorParams pf = pc;
  pf.dt_s = dt / static_cast<double>(ratio);
  const ReferenceTrace c = solve_reference_actuated(pc, coarse, force);
  const ReferenceTrace f = solve_reference_actuated(pf, fine, fine_force);
  double x_scale = 0.0, ex = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    x_scale = std::max(x_scale, std::fabs(c.x_r_m[n]));
    ex = std::max(ex, std::fabs(c.x_r_m[n] - f.x_r_m[n * ratio]));
    CHECK_EQUAL(f.stuck[n * ratio], c.stuck[n]);
  }
  CHECK(c.events > 50);
  LONGS_EQUAL(static_cast<long>(f.events), static_cast<long>(c.events));
  CHECK(ex / x_scale < 1e-12);
  test::note_margin("actuated reference coarse vs fine, relative", ex / x_scale, 1e-12);
}

// simulate's loop with the force (the core's exact integrator) against the reference with the
// same force: stick-slip with F_fs > F_fk on a lorry-like input at dt = 1 ms. The relative RMS of
// the a_x history stays within 1e-12 (the core's exact maps agree with the closed form to rounding;
// the events are located to 2^-16 of a step and then by Newton on the Taylor polynomial).
TEST(ActuatedReference, SimulateWithAForceAgreesWithTheReference) {
  const double dt = 1e-3;
  const std::size_t count = 20001;  // 20 s
  const std::vector<double> a_u = test::make_lorry_signal(9, 0.8).sample(dt, count);
  const std::vector<double> force = actuator_force(count, dt, 30.0);
  SimulationSetup setup;
  setup.params = seat(FrictionModel::stick_slip, dt, 40.0, 55.0);
  setup.repetitions = 1;
  setup.actuator_force_n = &force;
  SimulationTrace<double> core;
  simulate_signal(setup, a_u, core);
  const ReferenceTrace reference = solve_reference_actuated(setup.params, a_u, force);
  const double error = relative_rms(core.a_x_m_per_s2, reference.a_x_m_per_s2);
  long stuck = 0;
  for (std::uint8_t s : reference.stuck) stuck += s;
  CHECK(stuck > 1000 && stuck < 19000);  // the run both sticks and slips
  CHECK(reference.events > 100);
  CHECK(error < 1e-12);
  test::note_margin("simulate with f_a vs reference, a_x relative RMS", error, 1e-12);
  // The force matters: the run without it is far from the actuated one.
  SimulationSetup passive = setup;
  passive.actuator_force_n = nullptr;
  SimulationTrace<double> unforced;
  simulate_signal(passive, a_u, unforced);
  CHECK(relative_rms(unforced.a_x_m_per_s2, reference.a_x_m_per_s2) > 1e-2);
}

// The reference refuses a force vector of the wrong length or with a non-finite value.
TEST(ActuatedReference, RefusesAForceOfTheWrongLengthOrNotFinite) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 1e-3, 40.0, 50.0);
  const std::vector<double> a_u(10, 0.0);
  CHECK_THROWS(HostError, solve_reference_actuated(p, a_u, std::vector<double>(9, 0.0)));
  std::vector<double> bad(10, 0.0);
  bad[4] = std::nan("");
  CHECK_THROWS(HostError, solve_reference_actuated(p, a_u, bad));
}
