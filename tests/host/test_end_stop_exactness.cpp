// The core's seat with end stops (EndStopOscillator) against exact solutions: the plain
// oscillator where the stops are out of reach, the event-driven reference solver with end stops
// (itself checked against Dormand-Prince in test_reference_end_stops.cpp) in contact, and the
// energy of an undamped seat through a million steps with contacts. Figures are printed with
// STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <vector>

#include "../core/oracles.hpp"
#include "end_stop_scenarios.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
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
                         const std::vector<double>& a_u) {
  EndStopOscillator<double, Law> model;
  CHECK_TRUE(model.configure(p, s).ok());
  return counted_history(model, a_u);
}

double stuck_time(const History& h, double dt_s = kDt) {
  double sum = 0.0;
  for (const double f : h.stuck_fraction) sum += f;
  return sum * dt_s;
}

Deviation against_reference(const History& h, const ReferenceTrace& r, double dt_s = kDt) {
  return deviation(h.x, h.a_x, stuck_time(h, dt_s), r.x_r_m, r.a_x_m_per_s2, r.stuck_time_s,
                   dt_s * static_cast<double>(h.x.size() - 1));
}

// How far apart two exact solutions end whose inputs differ by 1e-13 (relative, either way):
// the rounding of the input alone moves the exact solution this far, so no solution computed in
// double can be checked against another more tightly. `solve` runs the reference on an input.
template <typename Solve>
Deviation spread_of(const Solve& solve, const std::vector<double>& a_u, const ReferenceTrace& exact,
                    double dt_s) {
  std::vector<double> up = a_u, down = a_u;
  for (std::size_t n = 0; n < a_u.size(); ++n) {
    up[n] *= 1.0 + 1e-13;
    down[n] *= 1.0 - 1e-13;
  }
  Deviation spread;
  for (const auto& other : {solve(up), solve(down)}) {
    const Deviation d = deviation(other.x_r_m, other.a_x_m_per_s2, other.stuck_time_s, exact.x_r_m,
                                  exact.a_x_m_per_s2, exact.stuck_time_s,
                                  dt_s * static_cast<double>(other.x_r_m.size() - 1));
    spread.x = std::max(spread.x, d.x);
    spread.a_x = std::max(spread.a_x, d.a_x);
    spread.t_ax = std::max(spread.t_ax, d.t_ax);
    spread.p = std::max(spread.p, d.p);
  }
  return spread;
}

Deviation spread_of_exact_solutions(const OscillatorParams& p, const EndStopParams& s,
                                    const std::vector<double>& a_u, const ReferenceTrace& exact) {
  return spread_of([&](const std::vector<double>& input) { return solve_reference(p, s, input); },
                   a_u, exact, p.dt_s);
}

// The stops at the RMS stroke of the seat without them: contacts in most cycles.
double rms_free_stroke(const OscillatorParams& p, const std::vector<double>& a_u) {
  return rms(solve_reference(p, a_u).x_r_m);
}

}  // namespace

TEST_GROUP(EndStopExactness){};

// Out of reach (10 m of travel) the stops change nothing: the seat is the plain oscillator on the
// same input, to the rounding of the two event searches (each locates v_r = 0 to rounding, on
// its own tick grid), with no damping anywhere.
TEST(EndStopExactness, StopsOutOfReachEqualThePlainOscillator) {
  const std::vector<double> a_u = wideband(0.35, 20.0, 5);
  {
    const OscillatorParams p = seat(FrictionModel::stick_slip, 0.0, 25.0, 30.0);
    Oscillator<double, CoulombStickSlip> plain;
    CHECK_TRUE(plain.configure(p).ok());
    const History want = run_history(plain, a_u);
    const History got = end_stop_history<CoulombStickSlip>(p, stops(10.0, 0.0), a_u);
    const Deviation d = deviation(got.x, got.a_x, stuck_time(got), want.x, want.a_x,
                                  stuck_time(want), kDt * static_cast<double>(got.x.size() - 1));
    print("out of reach, stick-slip", d);
    CHECK(stuck_time(want) > 1.0);  // the stick paths ran
    CHECK(d.x <= 1e-12);
    CHECK(d.a_x <= 1e-12);
  }
  {
    const OscillatorParams p = seat(FrictionModel::linear, 0.0, 0.0, 0.0);
    Oscillator<double, NoFriction> plain;
    CHECK_TRUE(plain.configure(p).ok());
    const History want = run_history(plain, a_u);
    const History got = end_stop_history<NoFriction>(p, stops(10.0, 0.0), a_u);
    const Deviation d = deviation(got.x, got.a_x, stuck_time(got), want.x, want.a_x,
                                  stuck_time(want), kDt * static_cast<double>(got.x.size() - 1));
    print("out of reach, frictionless", d);
    CHECK(d.x <= 1e-12);
    CHECK(d.a_x <= 1e-12);
  }
}

// The largest |x_r| difference between the end-stop model out of reach and the plain oscillator
// on `a_u`, relative to the plain seat's largest |x_r|; `dips` counts the plain seat's steps in
// which v_r crossed 0 and back (two events or more, slipping the same way at both ends).
template <typename Law>
double out_of_reach_x_difference(const OscillatorParams& p, const std::vector<double>& a_u,
                                 int& dips) {
  Oscillator<double, Law> plain;
  EndStopOscillator<double, Law> stopped;
  CHECK_TRUE(plain.configure(p).ok());
  CHECK_TRUE(stopped.configure(p, stops(10.0, 0.0)).ok());
  plain.reset(0.0, 0.0, a_u[0]);
  stopped.reset(0.0, 0.0, a_u[0]);
  double worst = 0.0, amplitude = 0.0, v_before = 0.0;
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<double> want = plain.step(a_u[n]);
    const StepOutput<double> got = stopped.step(a_u[n]);
    if (want.events >= 2 && v_before * want.v_r_m_per_s > 0.0) ++dips;
    v_before = want.v_r_m_per_s;
    amplitude = std::max(amplitude, std::fabs(want.x_r_m));
    worst = std::max(worst, std::fabs(got.x_r_m - want.x_r_m));
  }
  CHECK_EQUAL(0u, stopped.contacts());
  return worst / amplitude;
}

// White noise of +-30 m/s^2, a new level every sample: v_r often falls towards 0 and rises
// again inside one step, crossing 0 and back (a stick for a fraction of the step, or two
// reversals) where the step's ends show no change of sign. The search bisects such a step by the
// turn of v_r as the plain seat's does, so out of reach the two still agree to rounding, for
// both laws with a stuck state, damped and undamped, on several seeds.
TEST(EndStopExactness, StopsOutOfReachEqualThePlainOscillatorWhereVrDipsThroughZeroInAStep) {
  double worst = 0.0;
  int dips = 0;
  for (const double damping : {0.0, 504.0}) {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const std::vector<double> a_u = white_noise(30.0, seed);
      const OscillatorParams coulomb = seat(FrictionModel::stick_slip, damping, 25.0, 30.0);
      worst = std::max(worst, out_of_reach_x_difference<CoulombStickSlip>(coulomb, a_u, dips));
      OscillatorParams stribeck = seat(FrictionModel::stribeck, damping, 25.0, 30.0);
      stribeck.stribeck_velocity_m_per_s = 0.01;
      worst = std::max(worst, out_of_reach_x_difference<StribeckStickSlip>(stribeck, a_u, dips));
    }
  }
  test::note_margin("out of reach, v_r dipping through 0 in a step, x", worst, 1e-12);
  CHECK(dips > 0);  // the dips ran
  CHECK(worst <= 1e-12);
}

// In contact, with damping in the seat or in the stops, against the event-driven reference with
// end stops: the whole a_x history, T_ax and p to 1e-9 at dt = 1 ms over 20 s.
TEST(EndStopExactness, DampedContactMatchesTheExactSolution) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  struct Case {
    FrictionModel model;
    double seat_damping, stop_damping;
    const char* what;
  } cases[] = {{FrictionModel::stick_slip, 504.0, 2.0e3, "stick-slip, damped seat and stops"},
               {FrictionModel::stick_slip, 0.0, 2.0e3, "stick-slip, damped stops"},
               {FrictionModel::stick_slip, 504.0, 0.0, "stick-slip, damped seat"},
               {FrictionModel::linear, 0.0, 2.0e3, "frictionless, damped stops"},
               {FrictionModel::linear, 504.0, 0.0, "frictionless, damped seat"}};
  for (const Case& c : cases) {
    const bool sticking = c.model == FrictionModel::stick_slip;
    const OscillatorParams p = seat(c.model, c.seat_damping, sticking ? 25.0 : 0.0, 30.0);
    const EndStopParams s = stops(rms_free_stroke(p, a_u), c.stop_damping);
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    const History got = sticking ? end_stop_history<CoulombStickSlip>(p, s, a_u)
                                 : end_stop_history<NoFriction>(p, s, a_u);
    const Deviation d = against_reference(got, exact);
    print(c.what, d);
    test::note_margin("contacts", static_cast<double>(exact.contacts), 10.0);
    CHECK_TEXT(exact.contacts > 10, c.what);
    CHECK_EQUAL(exact.contacts, got.contacts);
    CHECK_EQUAL(0u, got.budget_exhausted);
    CHECK_TEXT(d.a_x <= 1e-9, c.what);
    CHECK_TEXT(d.t_ax <= 1e-9, c.what);
    CHECK_TEXT(d.p <= 1e-9, c.what);
  }
}

// Damped contact on other inputs, rates, seats and stops (wideband, lorry and harmonic floors;
// dt from 1/2 to 2 ms; stops of 5e4 to 1e6 N/m, damped in the seat, the stops or both). Where the
// problem lets the target be checked at all, i.e. two exact solutions whose inputs differ by 1e-13
// stay within 1e-10 of each other (a tenth of the target), the core is within 1e-9 of the exact
// solution; elsewhere (here: stiff stops damped only themselves, a seat without a damper between
// contacts) it is within that spread. Both kinds occur in the set, so neither branch is vacuous.
TEST(EndStopExactness, DampedContactOnOtherInputsAndRatesIsExactToTheProblemsConditioning) {
  struct Case {
    SignalKind kind;
    double rms, frequency_hz;
    std::uint64_t seed;
    double dt_s, seat_damping, travel_m, stop_stiffness, stop_damping, kinetic_n, static_n;
  } cases[] = {
      {SignalKind::lorry, 3.0, 0.0, 7241, 1e-3, 504.0, 0.03, 1e6, 2e3, 10.0, 12.0},
      {SignalKind::lorry, 3.0, 0.0, 2477, 1e-3, 200.0, 0.03, 5e4, 0.0, 10.0, 10.0},
      {SignalKind::lorry, 3.0, 0.0, 8294, 2e-3, 200.0, 0.01, 5e4, 0.0, 45.0, 45.0},
      {SignalKind::wideband, 3.0, 0.0, 48, 2e-3, 0.0, 0.02, 1e6, 500.0, 45.0, 45.0},
      {SignalKind::wideband, 1.0, 0.0, 7026, 5e-4, 0.0, 0.01, 2e5, 500.0, 10.0, 10.0},
      {SignalKind::wideband, 1.0, 0.0, 1046, 5e-4, 0.0, 0.005, 2e5, 2e3, 45.0, 54.0},
      {SignalKind::harmonic, 2.0, 1.5, 1, 1e-3, 504.0, 0.01, 2e5, 0.0, 25.0, 30.0},
      {SignalKind::harmonic, 3.0, 2.5, 1, 5e-4, 0.0, 0.01, 1e6, 1e3, 25.0, 25.0},
      {SignalKind::lorry, 3.0, 0.0, 6580, 1e-3, 0.0, 0.005, 1e6, 500.0, 25.0, 25.0},
  };
  int well_conditioned = 0, ill_conditioned = 0;
  for (const Case& c : cases) {
    const std::vector<double> a_u = floor_signal(c.kind, c.rms, c.dt_s, c.seed, c.frequency_hz);
    OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact,
                                                c.dt_s, c.seat_damping);
    p.kinetic_friction_n = c.kinetic_n;
    p.static_friction_n = c.static_n;
    EndStopParams s;
    s.travel_m = c.travel_m;
    s.stiffness_n_per_m = c.stop_stiffness;
    s.damping_ns_per_m = c.stop_damping;
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    const Deviation spread = spread_of_exact_solutions(p, s, a_u, exact);
    EndStopOscillator<double, CoulombStickSlip> model;
    CHECK_TRUE(model.configure(p, s).ok());
    const History got = counted_history(model, a_u, c.dt_s);
    const Deviation d = against_reference(got, exact, c.dt_s);
    print("other input, spread", spread);
    print("other input, core", d);
    CHECK(exact.contacts > 0);
    CHECK_EQUAL(exact.contacts, got.contacts);
    CHECK_EQUAL(0u, got.budget_exhausted);
    if (spread.a_x <= 1e-10) {
      ++well_conditioned;
      CHECK(d.a_x <= 1e-9);
      CHECK(d.t_ax <= 1e-9);
      CHECK(d.p <= 1e-9);
    } else {
      ++ill_conditioned;
      CHECK(d.a_x <= spread.a_x);
      CHECK(d.t_ax <= spread.t_ax);
      CHECK(d.p <= std::max(spread.p, 1e-9));
    }
  }
  CHECK(well_conditioned >= 6);
  CHECK(ill_conditioned >= 1);
}

// With nothing damped (b = 0, b_s = 0) rounding differences grow from contact to contact: the
// yardstick is how far two exact solutions drift apart whose inputs differ by 1e-13 (relative),
// measured here; the core stays within that spread of the exact solution.
TEST(EndStopExactness, UndampedContactStaysWithinTheSpreadOfExactSolutions) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 17);
  for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
    const bool sticking = model == FrictionModel::stick_slip;
    const OscillatorParams p = seat(model, 0.0, sticking ? 25.0 : 0.0, 30.0);
    const EndStopParams s = stops(rms_free_stroke(p, a_u), 0.0);
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    const Deviation spread = spread_of_exact_solutions(p, s, a_u, exact);
    const History got = sticking ? end_stop_history<CoulombStickSlip>(p, s, a_u)
                                 : end_stop_history<NoFriction>(p, s, a_u);
    const Deviation d = against_reference(got, exact);
    print(sticking ? "undamped stick-slip, spread" : "undamped frictionless, spread", spread);
    print(sticking ? "undamped stick-slip, core" : "undamped frictionless, core", d);
    CHECK(exact.contacts > 10);
    CHECK_EQUAL(exact.contacts, got.contacts);
    CHECK(d.x <= spread.x);
    CHECK(d.a_x <= spread.a_x);
    CHECK(d.t_ax <= spread.t_ax);
    CHECK(d.p <= spread.p);
  }
}

// An undamped scene drawn at random (seeded): a seat of 40-140 kg and 3.2e3-3.2e4 N/m with
// Coulomb stick-slip (F_fk 5 N to max_kinetic_n, F_fs up to 1.4 F_fk) or no friction, a
// wide-band (even i) or lorry floor of 0.5-3.5 m/s^2, stops of 3e4-1e6 N/m at 0.5-1.5 times the
// RMS free stroke; no damping anywhere.
namespace {
struct UndampedScene {
  OscillatorParams seat;
  EndStopParams stops;
  std::vector<double> a_u;
};
constexpr double kDts[3] = {5e-4, 1e-3, 2e-3};
UndampedScene random_undamped_scene(test::SplitMix64& draw, int i, bool sticking, double dt_s,
                                    double max_kinetic_n, std::uint64_t floor_seed) {
  UndampedScene scene;
  OscillatorParams& p = scene.seat;
  p = test::reference_params(sticking ? FrictionModel::stick_slip : FrictionModel::linear,
                             Integrator::exact, dt_s, 0.0);
  p.mass_kg = draw.uniform(40.0, 140.0);
  p.stiffness_n_per_m = std::pow(10.0, draw.uniform(3.5, 4.5));
  p.kinetic_friction_n = sticking ? draw.uniform(5.0, max_kinetic_n) : 0.0;
  p.static_friction_n = p.kinetic_friction_n * draw.uniform(1.0, 1.4);
  const SignalKind kind = i % 2 == 0 ? SignalKind::wideband : SignalKind::lorry;
  scene.a_u = floor_signal(kind, draw.uniform(0.5, 3.5), p.dt_s, floor_seed);
  scene.stops.travel_m = rms_free_stroke(p, scene.a_u) * draw.uniform(0.5, 1.5);
  scene.stops.stiffness_n_per_m = std::pow(10.0, draw.uniform(4.5, 6.0));
  scene.stops.damping_ns_per_m = 0.0;
  return scene;
}

// Calls `check` with a configurable end-stop seat of double: Coulomb stick-slip where `sticking`,
// else frictionless (the two laws the random scenes draw).
template <typename Check>
void with_end_stop_seat(bool sticking, const Check& check) {
  if (sticking) {
    EndStopOscillator<double, CoulombStickSlip> model;
    check(model);
  } else {
    EndStopOscillator<double, NoFriction> model;
    check(model);
  }
}

// The model's steps, each started from the exact solution's state at sample n, against its state
// at n + 1: the largest distance (x_r and v_r, relative to their RMS over the run) and how many
// steps were stuck, crossed a stop's edge, stayed in contact or stayed free.
struct StepsFromExactStates {
  double worst = 0.0;
  long stuck = 0, crossing = 0, contact = 0, free = 0;
};

template <typename Model>
void step_from_exact_states(Model& model, const EndStopParams& s, const std::vector<double>& a_u,
                            const ReferenceTrace& exact, StepsFromExactStates& steps) {
  const double x_scale = rms(exact.x_r_m), v_scale = rms(exact.v_r_m_per_s);
  for (std::size_t n = 0; n + 1 < a_u.size(); ++n) {
    model.reset(exact.x_r_m[n], exact.v_r_m_per_s[n], a_u[n]);
    const StepOutput<double> out = model.step(a_u[n + 1]);
    steps.worst = std::max({steps.worst, std::fabs(out.x_r_m - exact.x_r_m[n + 1]) / x_scale,
                            std::fabs(out.v_r_m_per_s - exact.v_r_m_per_s[n + 1]) / v_scale});
    const bool in0 = std::fabs(exact.x_r_m[n]) > s.travel_m;
    const bool in1 = std::fabs(exact.x_r_m[n + 1]) > s.travel_m;
    if (exact.v_r_m_per_s[n] == 0.0 && exact.v_r_m_per_s[n + 1] == 0.0) {
      ++steps.stuck;
    } else if (in0 != in1) {
      ++steps.crossing;
    } else {
      ++(in0 ? steps.contact : steps.free);
    }
  }
}
}  // namespace

// What the spread above cannot tell apart: a core that rounds every step but is exact, and one
// with a small error of its own, since with nothing damped both drift by more than the spread on
// some seats (an integrator rounds its state every step; an undamped seat between contacts keeps
// that rounding, and each contact can enlarge it). So each step is checked on its own: started
// from the exact solution's state at sample n, the core's step to n + 1 lands on the exact
// solution's state there. Seats drawn at random (seeded): 40-140 kg, 3.2e3-3.2e4 N/m, dt 1/2, 1
// or 2 ms, Coulomb stick-slip (F_fs up to 1.4 F_fk) or no friction, wide-band or lorry floors of
// 0.5-3.5 m/s^2, stops of 3e4-1e6 N/m at 0.5-1.5 times the RMS free stroke, no damping anywhere.
// Each side rounds a state of up to a few times its RMS through a dozen operations, and the
// exact solution also rounds its event times: 1.5e-14 of the RMS at most over 480 such seats;
// the tolerance is twice that. Steps free, in contact, across a contact boundary and stuck all
// occur in the set.
TEST(EndStopExactness, UndampedStepFromTheExactStateLandsOnTheExactSolutionToRounding) {
  test::SplitMix64 draw(20261129);
  StepsFromExactStates steps;
  for (int i = 0; i < 12; ++i) {
    const bool sticking = i % 3 != 2;
    const UndampedScene scene =
        random_undamped_scene(draw, i, sticking, kDts[i % 3], 65.0, 1 + std::uint64_t(i));
    const OscillatorParams& p = scene.seat;
    const EndStopParams& s = scene.stops;
    const std::vector<double>& a_u = scene.a_u;
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    const auto one_step = [&](auto& model) {
      CHECK_TRUE(model.configure(p, s).ok());
      step_from_exact_states(model, s, a_u, exact, steps);
    };
    with_end_stop_seat(sticking, one_step);
    CHECK(exact.contacts > 0);
  }
  test::note_margin("undamped, one step from the exact state (of the RMS)", steps.worst, 3e-14);
  CHECK(steps.worst <= 3e-14);
  CHECK(steps.free > 0);
  CHECK(steps.contact > 0);
  CHECK(steps.crossing > 0);
  CHECK(steps.stuck > 0);
}

// Random undamped seats (drawn as above, a third of them with Coulomb stick-slip, the others
// frictionless), each without stops and with stops in reach: the core's x_r and a_x histories end
// within the spread of exact solutions of each. The maps' diagonals decide it: kept as xx and vv,
// rounded to a double, they carry an error of the map's trace and determinant that an undamped
// seat keeps, and the core drifted above the spread on 63 of 87 frictionless seats without
// stops (by up to 8.3 times) and on 20 of 150 seats with stops; kept as xx - 1 and vv - 1
// (step_map.hpp) on none.
TEST(EndStopExactness, UndampedRandomSeatsStayWithinTheSpreadOfExactSolutions) {
  test::SplitMix64 draw(20261130);
  int seats = 0, with_contacts = 0;
  double worst_ratio = 0.0;
  for (int i = 0; i < 12; ++i) {
    const bool sticking = i % 3 == 0;
    const UndampedScene scene =
        random_undamped_scene(draw, i, sticking, kDts[(i / 3) % 3], 45.0, 40 + std::uint64_t(i));
    const OscillatorParams& p = scene.seat;
    const EndStopParams& s = scene.stops;
    const std::vector<double>& a_u = scene.a_u;
    const auto check_within = [&](const History& got, const ReferenceTrace& exact,
                                  const Deviation& spread) {
      const Deviation d = against_reference(got, exact, p.dt_s);
      CHECK(d.x <= spread.x);
      CHECK(d.a_x <= spread.a_x);
      worst_ratio = std::max(worst_ratio, d.a_x / spread.a_x);
      ++seats;
    };
    const ReferenceTrace free_exact = solve_reference(p, a_u);
    const Deviation free_spread =
        spread_of([&](const std::vector<double>& input) { return solve_reference(p, input); }, a_u,
                  free_exact, p.dt_s);
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    const Deviation spread = spread_of_exact_solutions(p, s, a_u, exact);
    const auto plain_and_with_stops = [&](auto law) {
      using Law = decltype(law);
      Oscillator<double, Law> plain;
      CHECK_TRUE(plain.configure(p).ok());
      check_within(run_history(plain, a_u, p.dt_s), free_exact, free_spread);
      EndStopOscillator<double, Law> model;
      CHECK_TRUE(model.configure(p, s).ok());
      check_within(counted_history(model, a_u, p.dt_s), exact, spread);
    };
    if (sticking) {
      plain_and_with_stops(CoulombStickSlip{});
    } else {
      plain_and_with_stops(NoFriction{});
    }
    with_contacts += exact.contacts > 0 ? 1 : 0;
  }
  test::note_margin("undamped random seats, a_x against the spread (ratio)", worst_ratio, 1.0);
  CHECK_EQUAL(24, seats);
  CHECK_EQUAL(12, with_contacts);
}

// Damped seats drawn at random (seeded): 40-140 kg, 3.2e3-3.2e4 N/m, dt 1/2, 1 or 2 ms, a damper
// of 30-900 N s/m in the seat, or in the stops (100-3,000 N s/m), or both; Coulomb stick-slip
// (F_fk 3-60 N, F_fs up to 1.4 F_fk) or no friction; wide-band, lorry or harmonic floors of
// 0.5-4 m/s^2 or white noise of up to +-20 m/s^2 a sample; stops of 3e4-1e6 N/m at 0.6-1.5 times
// the RMS free stroke. Every step, started from the exact solution's state, lands on it to
// rounding (as for the undamped seats above: 3e-14 of the RMS); the whole history is within 1e-9
// of the exact solution (a_x, T_ax, p) where two exact solutions whose inputs differ by 1e-13 stay
// within 1e-10 of each other. Where they do not (a lightly damped seat between undamped stiff
// stops: rounding-sized differences of the input grow to 1e-8 there), only the step is checked:
// any 1e-13 pattern of the input moves the exact solution as far as the core is from it.
TEST(EndStopExactness,
     DampedRandomSeatsStepOntoTheExactSolutionAndFollowItWhereItIsWellConditioned) {
  test::SplitMix64 draw(20261202);
  const SignalKind kinds[3] = {SignalKind::wideband, SignalKind::lorry, SignalKind::harmonic};
  double worst_history = 0.0;
  int scenes = 0, well_conditioned = 0, white = 0, sticking_scenes = 0;
  StepsFromExactStates steps;
  while (scenes < 12) {
    const int i = scenes;
    const bool sticking = i % 3 != 2;
    const double dt_s = kDts[draw.next() % 3];
    OscillatorParams p = test::reference_params(
        sticking ? FrictionModel::stick_slip : FrictionModel::linear, Integrator::exact, dt_s, 0.0);
    p.mass_kg = draw.uniform(40.0, 140.0);
    p.stiffness_n_per_m = std::pow(10.0, draw.uniform(3.5, 4.5));
    p.kinetic_friction_n = sticking ? draw.uniform(3.0, 60.0) : 0.0;
    p.static_friction_n = p.kinetic_friction_n * draw.uniform(1.0, 1.4);
    const int where = static_cast<int>(draw.next() % 3);  // 0: seat, 1: stops, 2: both
    p.damping_ns_per_m = where != 1 ? draw.uniform(30.0, 900.0) : 0.0;
    std::vector<double> a_u;
    const double level = draw.uniform(0.5, 4.0);
    const std::uint64_t floor_seed = draw.next() % 100000;
    if (i % 4 == 3) {
      a_u = white_noise(5.0 * level, floor_seed, dt_s);
    } else {
      a_u = floor_signal(kinds[i % 4 % 3], level, dt_s, floor_seed, draw.uniform(0.8, 4.0));
    }
    EndStopParams s;
    s.travel_m = rms_free_stroke(p, a_u) * draw.uniform(0.6, 1.5);
    s.stiffness_n_per_m = std::pow(10.0, draw.uniform(4.5, 6.0));
    s.damping_ns_per_m = where != 0 ? draw.uniform(100.0, 3000.0) : 0.0;
    if (!(s.travel_m > 1e-4)) continue;  // friction held the seat: no stroke to put stops at
    const ReferenceTrace exact = solve_reference(p, s, a_u);
    if (exact.contacts == 0) continue;
    ++scenes;
    white += i % 4 == 3 ? 1 : 0;
    sticking_scenes += sticking ? 1 : 0;
    const Deviation spread = spread_of_exact_solutions(p, s, a_u, exact);
    const auto check = [&](auto& model) {
      CHECK_TRUE(model.configure(p, s).ok());
      const History got = counted_history(model, a_u, dt_s);
      CHECK_EQUAL(exact.contacts, got.contacts);
      CHECK_EQUAL(0u, got.budget_exhausted);
      if (spread.a_x <= 1e-10) {
        ++well_conditioned;
        const Deviation d = against_reference(got, exact, dt_s);
        worst_history = std::max({worst_history, d.a_x, d.t_ax, d.p});
        CHECK(d.a_x <= 1e-9);
        CHECK(d.t_ax <= 1e-9);
        CHECK(d.p <= 1e-9);
      }
      step_from_exact_states(model, s, a_u, exact, steps);
    };
    with_end_stop_seat(sticking, check);
  }
  test::note_margin("damped random seats, one step from the exact state (of the RMS)", steps.worst,
                    3e-14);
  test::note_margin("damped random seats, well-conditioned histories", worst_history, 1e-9);
  CHECK(steps.worst <= 3e-14);
  CHECK(well_conditioned >= 6);
  CHECK(white >= 2);
  CHECK(sticking_scenes >= 6);
  CHECK(steps.contact + steps.crossing > 0);
  CHECK(steps.stuck > 0);
}

// No dissipation anywhere (no friction, b = 0, b_s = 0) and no input: the energy (spring, stop
// spring, kinetic) is conserved through a million steps with contacts, to 1e-9 of its start.
TEST(EndStopExactness, EnergyIsConservedOverAMillionStepsWithContacts) {
  const OscillatorParams p = seat(FrictionModel::linear, 0.0, 0.0, 0.0);
  EndStopOscillator<double, NoFriction> model;
  CHECK_TRUE(model.configure(p, stops(0.03, 0.0)).ok());
  model.reset(0.05, 0.0, 0.0);  // 2 cm into the upper stop, at rest
  const double e0 = model.energy_j();
  double worst = 0.0;
  for (int n = 0; n < 1000000; ++n) {
    model.step(0.0);
    worst = std::max(worst, std::fabs(model.energy_j() - e0));
  }
  test::note_margin("energy drift over 1e6 steps", worst / e0, 1e-9);
  CHECK(model.contacts() > 1000);
  CHECK(worst <= 1e-9 * e0);
}

// The same on stops of 5e4 and 1e7 N/m (omega dt up to 0.67 in contact) at dt = 1/2 and 2 ms,
// from inside a stop and from the free stroke moving, without friction and with Coulomb's at
// 0 N (whose every v_r = 0 is an event). Measured worst 2.0e-11.
// A step with a turn of v_r that reaches no boundary takes the mode's one whole-step map: the
// scan's 16 block maps would drift 1.06e-9 there (frictionless, 1e7 N/m, 2 ms, from 0.031 m).
template <typename Law>
double worst_energy_drift(FrictionModel friction, double stop_stiffness, double dt_s, double x0,
                          double v0, std::uint64_t& contacts) {
  OscillatorParams p = seat(friction, 0.0, 0.0, 0.0);
  p.dt_s = dt_s;
  EndStopParams s = stops(0.03, 0.0);
  s.stiffness_n_per_m = stop_stiffness;
  EndStopOscillator<double, Law> model;
  CHECK_TRUE(model.configure(p, s).ok());
  model.reset(x0, v0, 0.0);
  const double e0 = model.energy_j();
  double worst = 0.0;
  for (int n = 0; n < 1000000; ++n) {
    model.step(0.0);
    worst = std::max(worst, std::fabs(model.energy_j() - e0));
  }
  contacts = model.contacts();
  return worst / e0;
}

TEST(EndStopExactness, EnergyIsConservedOnStiffStopsAtOtherRates) {
  double worst = 0.0;
  for (const double stiffness : {5.0e4, 1.0e7}) {
    for (const double dt_s : {5e-4, 2e-3}) {
      for (const double x0 : {0.031, -0.2}) {
        std::uint64_t contacts = 0, sticking_contacts = 0;
        const double frictionless = worst_energy_drift<NoFriction>(FrictionModel::linear, stiffness,
                                                                   dt_s, x0, 0.7, contacts);
        const double coulomb = worst_energy_drift<CoulombStickSlip>(
            FrictionModel::stick_slip, stiffness, dt_s, x0, 0.7, sticking_contacts);
        CHECK(contacts > 1000);
        CHECK_EQUAL(contacts, sticking_contacts);
        CHECK(frictionless <= 1e-9);
        CHECK(coulomb <= 1e-9);
        worst = std::max({worst, frictionless, coulomb});
      }
    }
  }
  test::note_margin("energy drift over 1e6 steps, stiff stops and other rates", worst, 1e-9);
}

// Steps spent wholly inside a stiff stop (1e8 N/m, omega dt = 2.1 there; no damping, no input):
// the energy moves by the rounding of the contact map alone, about 2e-16 a step either way, and
// on average by no more than the rounding of the map's determinant, eps (|xx vv| + |xv vx|) = eps
// here (test_passivity.cpp). With the maps on x_r itself, whose terms of the size of the travel
// cancel to the penetration, and the exponential unbalanced, it rose by 7.4e-15 a step on
// average: 1e-9 of drift in 1e6 steps from these steps alone.
TEST(EndStopExactness, StepsInsideAStiffStopMoveTheEnergyByTheMapsRoundingAlone) {
  OscillatorParams p = seat(FrictionModel::linear, 0.0, 0.0, 0.0);
  p.dt_s = 2e-3;
  EndStopParams s = stops(0.02, 0.0);
  s.stiffness_n_per_m = 1e8;
  EndStopOscillator<double, NoFriction> model;
  CHECK_TRUE(model.configure(p, s).ok());
  model.reset(0.03, 0.0, 0.0);
  const double e0 = model.energy_j();
  double sum = 0.0;
  long inside = 0;
  for (int n = 0; n < 200000; ++n) {
    const int before = model.contact();
    const double e = model.energy_j();
    const StepOutput<double> out = model.step(0.0);
    if (before != 0 && model.contact() == before && out.events == 0 &&
        model.last_step_contacts().contact_events == 0) {
      sum += (model.energy_j() - e) / e0;
      ++inside;
    }
  }
  const double mean = sum / double(inside);
  const double eps = std::numeric_limits<double>::epsilon();
  test::note_margin("energy change a step inside a stiff stop, mean", std::fabs(mean), eps);
  CHECK(inside > 10000);
  CHECK(std::fabs(mean) <= eps);
}

// Float: the same engine at float's rounding. Against the exact solution on the damped contact
// scene: measured a_x 1.7e-6 RMS, T_ax 5.1e-7, p 3.4e-8 (the plain float oscillator on this input
// without stops: a_x 6.3e-7). Float's ulp of x_r is about the motion of one 2^-16 tick near the
// stops, so contacts are placed to a tick where the double engine solves for them.
TEST(EndStopExactness, FloatDampedContactIsExactToFloatRounding) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(rms_free_stroke(p, a_u), 2.0e3);
  const ReferenceTrace exact = solve_reference(p, s, a_u);
  EndStopOscillator<float, CoulombStickSlip> model;
  CHECK_TRUE(model.configure(p, s).ok());
  model.reset(0.0f, 0.0f, static_cast<float>(a_u[0]));
  History got;
  got.x.push_back(0.0);
  got.a_x.push_back(static_cast<double>(model.current().a_x_m_per_s2));
  got.stuck_fraction.push_back(0.0);
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<float> out = model.step(static_cast<float>(a_u[n]));
    got.x.push_back(static_cast<double>(out.x_r_m));
    got.a_x.push_back(static_cast<double>(out.a_x_m_per_s2));
    got.stuck_fraction.push_back(static_cast<double>(out.stuck_fraction));
  }
  const Deviation d = against_reference(got, exact);
  print("float, stick-slip, damped seat and stops", d);
  CHECK_EQUAL(exact.contacts, model.contacts());
  CHECK_EQUAL(0u, model.event_budget_exhausted());
  CHECK(d.a_x <= 1e-5);
  CHECK(d.t_ax <= 1e-5);
  CHECK(d.p <= 1e-5);
}
