// The seat with end stops and Gaussian Stribeck friction (EndStopOscillator<T, StribeckStickSlip>)
// against: the plain Stribeck oscillator where the stops are out of reach, the Coulomb end-stop
// model where the Stribeck law is flat (F_fs = F_fk), and the event-driven reference with end
// stops in contact (itself checked against Dormand-Prince in test_reference_end_stops.cpp), at
// shrinking dt: the slip friction is held over each piece of motion, so the error is first order
// in dt. Figures are printed with STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../core/oracles.hpp"
#include "end_stop_scenarios.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

// The shared scenes, seats and histories (end_stop_scenarios.hpp).
using namespace test::end_stop;

template <typename Law>
History end_stop_history(const OscillatorParams& p, const EndStopParams& s,
                         const std::vector<double>& a_u, std::size_t keep = 1) {
  EndStopOscillator<double, Law> model;
  const ConfigResult configured = model.configure(p, s);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  return counted_history(model, a_u, p.dt_s, keep);
}

// The FOH input a_u (samples kDt apart) sampled `factor` times finer: the same piecewise linear
// function of time, so every dt sees the same floor.
std::vector<double> finer(const std::vector<double>& a_u, std::size_t factor) {
  std::vector<double> out;
  out.reserve((a_u.size() - 1) * factor + 1);
  for (std::size_t n = 0; n + 1 < a_u.size(); ++n) {
    for (std::size_t j = 0; j < factor; ++j) {
      const double phi = static_cast<double>(j) / static_cast<double>(factor);
      out.push_back(a_u[n] + phi * (a_u[n + 1] - a_u[n]));
    }
  }
  out.push_back(a_u.back());
  return out;
}

OscillatorParams stribeck_seat(double damping, double kinetic_n, double static_n) {
  OscillatorParams p = seat(FrictionModel::stribeck, damping, kinetic_n, static_n);
  p.stribeck_velocity_m_per_s = 0.01;
  return p;
}

// The stops at the RMS stroke of the seat without them (the plain oscillator's run): contacts in
// most cycles.
double rms_free_stroke(const OscillatorParams& p, const std::vector<double>& a_u) {
  Oscillator<double, StribeckStickSlip> plain;
  CHECK_TRUE(plain.configure(p).ok());
  return rms(run_history(plain, a_u, p.dt_s, 1).x);
}

}  // namespace

TEST_GROUP(EndStopStribeck){};

// Out of reach (10 m of travel) the stops change nothing: the plain Stribeck oscillator's exact
// integrator holds the friction over each piece of motion as the end-stop model does, so the
// two agree to the rounding of their event searches (each locates v_r = 0 to rounding on its own
// tick grid). Undamped, so that nothing hides a difference.
TEST(EndStopStribeck, StopsOutOfReachEqualThePlainStribeckOscillator) {
  const std::vector<double> a_u = wideband(0.35, 20.0, 5);
  for (const double damping : {0.0, 504.0}) {
    const OscillatorParams p = stribeck_seat(damping, 25.0, 30.0);
    Oscillator<double, StribeckStickSlip> plain;
    CHECK_TRUE(plain.configure(p).ok());
    const History want = run_history(plain, a_u, kDt, 1);
    const History got = end_stop_history<StribeckStickSlip>(p, stops(10.0, 0.0), a_u);
    const Deviation d = deviation(got, want, 20.0);
    print(damping > 0 ? "out of reach, stribeck, damped" : "out of reach, stribeck, undamped", d);
    CHECK(want.stuck_s > 1.0);  // the stick paths ran
    CHECK_EQUAL(0u, got.contacts);
    CHECK(d.x <= 1e-12);
    CHECK(d.a_x <= 1e-12);
    CHECK(d.p <= 1e-12);
  }
}

// The same where the plain oscillator's event search bisects the step (a tick level above 0:
// rate * dt above 1/16, from a stiffer seat or a longer step): a piece of slip that begins or
// ends inside the step is still held at the force where it starts, not re-sampled at the
// blocks the search visits, so the two models agree to rounding at every rate, other seats,
// floors and Stribeck velocities included.
TEST(EndStopStribeck, StopsOutOfReachEqualThePlainStribeckOscillatorWhereItsSearchBisects) {
  struct Case {
    double mass_kg, stiffness, damping, dt_s, kinetic_n, static_n, stribeck_m_per_s;
    SignalKind kind;
    double rms;
    std::uint64_t seed;
  } cases[] = {
      {88.4, 11500.0, 504.0, 4e-3, 25.0, 30.0, 0.01, SignalKind::wideband, 0.8, 3},
      {61.0, 20531.0, 0.0, 3.59e-3, 23.0, 31.0, 0.002, SignalKind::wideband, 2.0, 61},
      {50.0, 30000.0, 800.0, 3e-3, 12.0, 18.0, 0.015, SignalKind::lorry, 0.5, 8},
      {88.4, 11500.0, 0.0, 8e-3, 30.0, 39.0, 0.04, SignalKind::lorry, 1.5, 17},
  };
  for (const Case& c : cases) {
    OscillatorParams p = stribeck_seat(c.damping, c.kinetic_n, c.static_n);
    p.mass_kg = c.mass_kg;
    p.stiffness_n_per_m = c.stiffness;
    p.dt_s = c.dt_s;
    p.stribeck_velocity_m_per_s = c.stribeck_m_per_s;
    CHECK(event_search_plan(p, 0x1p-52).tick_level > 0);
    const std::vector<double> a_u = floor_signal(c.kind, c.rms, c.dt_s, c.seed);
    Oscillator<double, StribeckStickSlip> plain;
    CHECK_TRUE(plain.configure(p).ok());
    const History want = run_history(plain, a_u, c.dt_s, 1);
    const History got = end_stop_history<StribeckStickSlip>(p, stops(10.0, 0.0), a_u);
    const Deviation d = deviation(got, want, c.dt_s * static_cast<double>(a_u.size() - 1));
    print("out of reach, stribeck, search bisecting", d);
    test::note_margin("stribeck, search bisecting: stuck s", want.stuck_s, 0.01);
    CHECK(want.stuck_s > 0.01);  // sticks and break-aways inside steps, besides the reversals
    CHECK_EQUAL(0u, got.contacts);
    CHECK(d.x <= 1e-12);
    CHECK(d.a_x <= 1e-12);
    CHECK(d.p <= 1e-12);
  }
}

// A flat Stribeck law (F_fs = F_fk) is Coulomb stick-slip: the held force (F_fk + 0 exp(..)) d is
// F_fk d exactly, so the two end-stop models agree bit for bit, contacts and sticks included.
TEST(EndStopStribeck, FlatStribeckWithStopsIsCoulombWithStopsBitForBit) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  OscillatorParams p = stribeck_seat(504.0, 25.0, 25.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u), 2.0e3);
  const History got = end_stop_history<StribeckStickSlip>(p, s, a_u);
  p.model = FrictionModel::stick_slip;
  const History want = end_stop_history<CoulombStickSlip>(p, s, a_u);
  test::note_margin("flat stribeck: stuck s", want.stuck_s, 0.0);
  CHECK(want.contacts > 10);
  CHECK(want.stuck_s > 0.01);
  CHECK_EQUAL(want.contacts, got.contacts);
  CHECK_TRUE(want.x == got.x);
  CHECK_TRUE(want.a_x == got.a_x);
  CHECK_TRUE(want.friction == got.friction);
  CHECK_EQUAL(want.stuck_s, got.stuck_s);
}

// In contact against the reference with end stops (Stribeck slip integrated to 1e-15): the
// friction held over each piece of motion makes the error first order in dt. At dt = 1, 1/2, 1/4
// and 1/8 ms on the same floor (the 1 ms FOH input sampled finer), compared at the 1 ms samples.
// An event (stick, reversal) placed a little off moves a_x by up to 2 F_fs/m at a sample that
// falls between the two instants: such samples (the model in another mode than the reference)
// are counted, not averaged. Every halving of dt must halve the x, a_x (samples in the same
// mode) and p errors to order >= 0.9, and the mode may differ at no more than 3 of the 10^4
// samples (measured: 3, 3, 1, 1).
TEST(EndStopStribeck, ContactConvergesToTheReferenceAtFirstOrderInDt) {
  const std::vector<double> a_u = wideband(2.0, 10.0, 13);
  const OscillatorParams p = stribeck_seat(504.0, 25.0, 30.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u), 2.0e3);
  const ReferenceTrace exact = solve_reference(p, s, a_u);
  CHECK(exact.contacts > 10);
  CHECK(exact.events > 10);
  const double a_scale = rms(exact.a_x_m_per_s2);
  double previous[3] = {0.0, 0.0, 0.0};
  for (const std::size_t factor : {1u, 2u, 4u, 8u}) {
    OscillatorParams fine = p;
    fine.dt_s = kDt / static_cast<double>(factor);
    const History got = end_stop_history<StribeckStickSlip>(fine, s, finer(a_u, factor), factor);
    const Deviation d = deviation(got.x, got.a_x, got.stuck_s, exact.x_r_m, exact.a_x_m_per_s2,
                                  exact.stuck_time_s, 10.0);
    std::size_t other_mode = 0, same_mode = 0;
    double error = 0.0;
    for (std::size_t n = 0; n < got.x.size(); ++n) {
      const bool same =
          got.stuck[n] == exact.stuck[n] &&
          (got.stuck[n] != 0 || (got.friction[n] > 0.0) == (exact.friction_n[n] > 0.0));
      if (!same) {
        ++other_mode;
        continue;
      }
      ++same_mode;
      error += (got.a_x[n] - exact.a_x_m_per_s2[n]) * (got.a_x[n] - exact.a_x_m_per_s2[n]);
    }
    const double a_same = std::sqrt(error / static_cast<double>(same_mode)) / a_scale;
    char what[64];
    std::snprintf(what, sizeof what, "stribeck in contact, dt = 1/%zu ms", factor);
    print(what, d);
    test::note_margin("  a_x rms, samples in the same mode", a_same, 0.0);
    test::note_margin("  samples in another mode", static_cast<double>(other_mode), 3.0);
    CHECK_EQUAL(0u, got.budget_exhausted);
    CHECK_TEXT(other_mode <= 3, what);
    const double now[3] = {d.x, a_same, d.p};
    if (factor > 1) {
      const char* names[3] = {"x", "a_x", "p"};
      for (int i = 0; i < 3; ++i) {
        const double order = std::log2(previous[i] / now[i]);
        test::note_margin(names[i], order, 0.9);
        CHECK_TEXT(order >= 0.9, what);
      }
    }
    for (int i = 0; i < 3; ++i) previous[i] = now[i];
    if (factor == 8) CHECK_EQUAL(exact.contacts, got.contacts);
  }
}

// Float: the same model at float's rounding stays with the double one on the contact scene
// (the difference is float's rounding, far below the first-order error of either).
TEST(EndStopStribeck, FloatFollowsDoubleInContact) {
  const std::vector<double> a_u = wideband(2.0, 10.0, 13);
  const OscillatorParams p = stribeck_seat(504.0, 25.0, 30.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u), 2.0e3);
  const History want = end_stop_history<StribeckStickSlip>(p, s, a_u);
  EndStopOscillator<float, StribeckStickSlip> model;
  CHECK_TRUE(model.configure(p, s).ok());
  const History got = run_history(model, a_u);
  const Deviation d = deviation(got, want, 10.0);
  print("float vs double, stribeck in contact", d);
  CHECK_EQUAL(want.contacts, model.contacts());
  CHECK_EQUAL(0u, model.event_budget_exhausted());
  // Measured a_x 2.1e-6 RMS, T_ax 9.7e-8, p 8.2e-9 (float's epsilon 6e-8, grown through the
  // contacts and sticks of 10 s).
  CHECK(d.a_x <= 1e-5);
  CHECK(d.t_ax <= 1e-6);
  CHECK(d.p <= 1e-7);
}
