// The actuator force on the seat with end stops: EndStopOscillator::step(a_u, f_a) and simulate's
// loop with an f_a column on an end-stop scene, against the event-driven reference with end stops
// and the same force (solve_reference_actuated, itself checked against Dormand-Prince in
// test_reference_end_stops.cpp). Figures are printed with STICKSLIP_TEST_MARGINS=1.
//   m dv_r/dt + b v_r + k x_r + F_stop + F_f = -m a_u + f_a,   F_L = f_a - (m a_u + k x_r + F_stop)
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "../core/oracles.hpp"
#include "end_stop_scenarios.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/end_stops.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

using test::end_stop::kDt;
using test::end_stop::seat;
using test::end_stop::stops;
using test::end_stop::wideband;

// What a controller's output stage holds: a level that steps every 37 samples (F_L jumps at
// those samples, beyond F_fs for some) plus two sines that change it at every sample.
std::vector<double> actuator_force(std::size_t count, double amplitude_n) {
  std::vector<double> f(count);
  test::SplitMix64 random(5);
  double level = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    const double t = static_cast<double>(n) * kDt;
    if (n % 37 == 0) level = random.uniform(-amplitude_n, amplitude_n);
    f[n] = level + 0.5 * amplitude_n * std::sin(2.0 * test::kPi * 1.3 * t) +
           0.2 * amplitude_n * std::sin(2.0 * test::kPi * 7.1 * t + 0.4);
  }
  return f;
}

double rms(const std::vector<double>& a) {
  double sum = 0.0;
  for (const double v : a) sum += v * v;
  return std::sqrt(sum / static_cast<double>(a.size()));
}

double relative_rms(const std::vector<double>& value, const std::vector<double>& oracle) {
  double error = 0.0, norm = 0.0;
  for (std::size_t n = 0; n < oracle.size(); ++n) {
    error += (value[n] - oracle[n]) * (value[n] - oracle[n]);
    norm += oracle[n] * oracle[n];
  }
  return std::sqrt(error / norm);
}

// The stops at the RMS stroke of the seat without them: contacts in most cycles.
double rms_free_stroke(const OscillatorParams& p, const std::vector<double>& a_u,
                       const std::vector<double>& f_a) {
  return rms(solve_reference_actuated(p, a_u, f_a).x_r_m);
}

SimulationSetup end_stop_setup(const OscillatorParams& p, const EndStopParams& s,
                               const std::vector<double>* f_a) {
  SimulationSetup setup;
  setup.params = p;
  setup.repetitions = 1;
  setup.effects = kSpring | kDamper | kEndStops |
                  (p.model == FrictionModel::linear ? 0u : kCoulomb | kStaticFriction);
  setup.stops = s;
  setup.actuator_force_n = f_a;
  return setup;
}

void print(const char* what, double a_x, double t_ax, double p) {
  if (std::getenv("STICKSLIP_TEST_MARGINS") == nullptr) return;
  std::printf("\n    [figure] %s: a_x rms %.3e, T_ax %.3e, p %.3e", what, a_x, t_ax, p);
}

}  // namespace

TEST_GROUP(EndStopActuator){};

// simulate with an f_a column on an end-stop scene, damped in the seat or the stops, against the
// reference with the same force: the whole a_x history, T_ax and p to 1e-9 at dt = 1 ms over
// 20 s, the tolerance of the end-stop exactness tests without force (the core's maps are exact
// and its events are solved for to rounding; what remains is rounding carried from contact to
// contact, which the damping keeps small).
TEST(EndStopActuator, SimulateWithAForceOnEndStopsMatchesTheExactSolution) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  const std::vector<double> f_a = actuator_force(a_u.size(), 40.0);
  struct Case {
    FrictionModel model;
    double seat_damping, stop_damping, kinetic_n, static_n;
    const char* what;
  } cases[] = {
      {FrictionModel::stick_slip, 504.0, 2.0e3, 25.0, 30.0, "actuated stick-slip, damped"},
      {FrictionModel::stick_slip, 0.0, 2.0e3, 25.0, 30.0, "actuated stick-slip, damped stops"},
      {FrictionModel::stick_slip, 504.0, 0.0, 25.0, 30.0, "actuated stick-slip, damped seat"},
      // Sticking a large part of the time: the force's jumps break the seat away at samples.
      {FrictionModel::stick_slip, 504.0, 2.0e3, 90.0, 120.0, "actuated stick-slip, sticky"},
      {FrictionModel::linear, 0.0, 2.0e3, 0.0, 0.0, "actuated frictionless, damped stops"},
      {FrictionModel::linear, 504.0, 0.0, 0.0, 0.0, "actuated frictionless, damped seat"}};
  for (const Case& c : cases) {
    const bool sticking = c.model == FrictionModel::stick_slip;
    const OscillatorParams p = seat(c.model, c.seat_damping, c.kinetic_n, c.static_n);
    const EndStopParams s = stops(rms_free_stroke(p, a_u, f_a), c.stop_damping);
    const ReferenceTrace exact = solve_reference_actuated(p, s, a_u, f_a);
    SimulationTrace<double> core;
    const SimulationSetup setup = end_stop_setup(p, s, &f_a);
    const SimulationSummary summary = simulate_signal(setup, a_u, core);
    const double a_x = relative_rms(core.a_x_m_per_s2, exact.a_x_m_per_s2);
    const double t_ax =
        std::fabs(rms(core.a_x_m_per_s2) - rms(exact.a_x_m_per_s2)) / rms(exact.a_x_m_per_s2);
    const double duration = kDt * static_cast<double>(a_u.size() - 1);
    const double p_error = std::fabs(summary.stick_probability - exact.stuck_time_s / duration);
    print(c.what, a_x, t_ax, p_error);
    if (std::getenv("STICKSLIP_TEST_MARGINS") != nullptr)
      std::printf(" stuck %.3f of the time, %llu events, %llu contacts",
                  exact.stuck_time_s / duration, (unsigned long long)exact.events,
                  (unsigned long long)exact.contacts);
    test::note_margin("contacts", static_cast<double>(exact.contacts), 10.0);
    CHECK_TEXT(exact.contacts > 10, c.what);
    CHECK_EQUAL(0u, summary.event_budget_exhausted);
    if (sticking) CHECK_TEXT(exact.events > 100, c.what);  // it sticks and breaks away
    CHECK_TEXT(a_x <= 1e-9, c.what);
    CHECK_TEXT(t_ax <= 1e-9, c.what);
    CHECK_TEXT(p_error <= 1e-9, c.what);
    // The force matters: without it the run is far from the actuated one.
    SimulationTrace<double> passive;
    simulate_signal(end_stop_setup(p, s, nullptr), a_u, passive);
    CHECK_TEXT(relative_rms(passive.a_x_m_per_s2, exact.a_x_m_per_s2) > 1e-2, c.what);
  }
}

// The model's own counts: the contacts of the actuated core equal the reference's.
TEST(EndStopActuator, ContactsWithAForceEqualTheReference) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  const std::vector<double> f_a = actuator_force(a_u.size(), 40.0);
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u, f_a), 2.0e3);
  const ReferenceTrace exact = solve_reference_actuated(p, s, a_u, f_a);
  EndStopOscillator<double, CoulombStickSlip> model;
  CHECK_TRUE(model.configure(p, s).ok());
  model.reset(0.0, 0.0, a_u[0], f_a[0]);
  for (std::size_t n = 1; n < a_u.size(); ++n) model.step(a_u[n], f_a[n]);
  CHECK(exact.contacts > 10);
  CHECK_EQUAL(exact.contacts, model.contacts());
  CHECK_EQUAL(0u, model.event_budget_exhausted());
}

// A force that jumps at a sample while the seat is held: F_L beyond F_fs at the step's start
// breaks the seat away there, in the core as in the reference. Seat held at rest against its
// upper stop edge (x_r = travel / 2), floor still; the force steps from 0 to 80 N (F_L = 80 - k x
// beyond F_fs = 30) and back to 0 after 5 samples.
TEST(EndStopActuator, AForceStepBeyondStaticFrictionBreaksAwayAtTheStepStart) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(0.01, 2.0e3);
  const std::size_t count = 400;
  const std::vector<double> a_u(count, 0.0);
  std::vector<double> f_a(count, 0.0);
  for (std::size_t n = 10; n < 15; ++n) f_a[n] = 80.0;
  const double x0 = 0.2 * 30.0 / p.stiffness_n_per_m;  // held: |k x0| < F_fs
  const ReferenceTrace exact = solve_reference_actuated(p, s, a_u, f_a, x0);
  EndStopOscillator<double, CoulombStickSlip> model;
  CHECK_TRUE(model.configure(p, s).ok());
  model.reset(x0, 0.0, 0.0, 0.0);
  CHECK_TRUE(model.stuck());
  std::vector<double> a_x(count);
  a_x[0] = model.current_with_force(f_a[0]).a_x_m_per_s2;
  std::vector<std::uint8_t> stuck(count);
  stuck[0] = 1;
  for (std::size_t n = 1; n < count; ++n) {
    const StepOutput<double> out = model.step(a_u[n], f_a[n]);
    a_x[n] = out.a_x_m_per_s2;
    stuck[n] = out.stuck ? 1 : 0;
    if (n == 10) {
      CHECK_FALSE(out.stuck);  // left at the start of the step the force came with
      CHECK_EQUAL(0.0, out.stuck_fraction);
    }
  }
  CHECK_EQUAL(1, exact.stuck[9]);
  CHECK_EQUAL(0, exact.stuck[10]);
  for (std::size_t n = 0; n < count; ++n) CHECK_EQUAL(exact.stuck[n], stuck[n]);
  const double error = relative_rms(a_x, exact.a_x_m_per_s2);
  test::note_margin("force step at rest, a_x relative RMS", error, 1e-12);
  CHECK(error <= 1e-12);  // a few events, each solved for to rounding
}

// step(a_u, 0) is step(a_u) bit for bit (the passive step forms no offset; with a zero force the
// actuated step's every value is the same), through contacts, sticking and break-away.
TEST(EndStopActuator, AZeroForceIsThePassiveStepBitForBit) {
  const std::vector<double> a_u = wideband(2.0, 5.0, 13);
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(0.004, 2.0e3);
  EndStopOscillator<double, CoulombStickSlip> passive, actuated;
  CHECK_TRUE(passive.configure(p, s).ok());
  CHECK_TRUE(actuated.configure(p, s).ok());
  passive.reset(0.0, 0.0, a_u[0]);
  actuated.reset(0.0, 0.0, a_u[0], 0.0);
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<double> a = passive.step(a_u[n]);
    const StepOutput<double> b = actuated.step(a_u[n], 0.0);
    CHECK_EQUAL(0, std::memcmp(&a.x_r_m, &b.x_r_m, sizeof(double)));
    CHECK_EQUAL(0, std::memcmp(&a.v_r_m_per_s, &b.v_r_m_per_s, sizeof(double)));
    CHECK_EQUAL(0, std::memcmp(&a.a_x_m_per_s2, &b.a_x_m_per_s2, sizeof(double)));
    CHECK_EQUAL(0, std::memcmp(&a.friction_n, &b.friction_n, sizeof(double)));
    CHECK_EQUAL(a.stuck, b.stuck);
  }
  CHECK(passive.contacts() > 10);
  CHECK_EQUAL(passive.contacts(), actuated.contacts());
}

// Float: the same engine at float's rounding with the force, against the exact solution on the
// damped contact scene, to the bound of the passive float test (1e-5: float's ulp of x_r is about
// the motion of one 2^-16 tick near the stops).
TEST(EndStopActuator, FloatWithAForceIsExactToFloatRounding) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  const std::vector<double> f_a = actuator_force(a_u.size(), 40.0);
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u, f_a), 2.0e3);
  const ReferenceTrace exact = solve_reference_actuated(p, s, a_u, f_a);
  SimulationTrace<float> core;
  const std::vector<float> input(a_u.begin(), a_u.end());
  simulate_signal(end_stop_setup(p, s, &f_a), input, core);
  const std::vector<double> a_x(core.a_x_m_per_s2.begin(), core.a_x_m_per_s2.end());
  const double error = relative_rms(a_x, exact.a_x_m_per_s2);
  print("float, actuated stick-slip, damped", error, 0.0, 0.0);
  CHECK(exact.contacts > 10);
  CHECK(error <= 1e-5);
}
