// The reference solver (sim_host reference_solver.hpp) against closed forms: the FOH frequency
// response of the linear seat, Coulomb free decay, constant base acceleration, and the same FOH
// input at a coarse and a 50x finer sampling (events inside sample intervals). The closed forms
// come from tests/core/oracles.hpp, which never calls a solver. Worst errors are printed with
// STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "../core/oracles.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/run/simulation.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;
using stickslip::test::kPi;

namespace {

constexpr double kMass = test::kMassKg;
constexpr double kStiffness = test::kStiffnessNPerM;
const double kCriticalDamping = 2.0 * std::sqrt(kStiffness * kMass);

OscillatorParams seat(FrictionModel model, double dt_s, double damping, double kinetic_n = 0.0,
                      double static_n = 0.0) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, dt_s, damping);
  p.kinetic_friction_n = kinetic_n;
  p.static_friction_n = static_n;
  return p;
}

// --- frequency response ------------------------------------------------------------------------
struct FrfError {
  double x = 0.0, v = 0.0, a_x = 0.0;  // max pointwise error over the run / amplitude
};

// e^{i w n dt} with the phase in long double: a double phase w n dt would be off by ~1e-13 rad
// after 1000 rad, a jitter on the input that the 1e-12 comparison would see.
std::complex<double> phasor(double w, std::size_t n, double dt_s) {
  const long double theta =
      static_cast<long double>(w) * static_cast<long double>(n) * static_cast<long double>(dt_s);
  return {static_cast<double>(std::cos(theta)), static_cast<double>(std::sin(theta))};
}

// a_u[n] = cos(w n dt) from the exact steady state (x0, v0) = Re(X, V): the response at every
// sample is then Re(e^{i w n dt} (X, V)), with no transient to wait for.
FrfError run_frf(double frequency_hz, double dt_s, double damping, double duration_s) {
  const double w = 2.0 * kPi * frequency_hz;
  // 1e5 aliasing terms: with 2000 the truncated tail alone reaches 1e-12 for the heavily damped
  // seat at dt = 10 ms (its H falls off only as 1/w up to b/m).
  const auto oracle = test::foh_phasor_response(kMass, damping, kStiffness, w, dt_s, 100000);
  const auto count = static_cast<std::size_t>(std::lround(duration_s / dt_s)) + 1;
  std::vector<double> a_u(count);
  for (std::size_t n = 0; n < count; ++n) a_u[n] = phasor(w, n, dt_s).real();
  const ReferenceTrace trace = solve_reference(seat(FrictionModel::linear, dt_s, damping), a_u,
                                               oracle.x_m.real(), oracle.v_m_per_s.real());
  // a_x = -(k x + b v)/m, amplitude |k X + b V|/m.
  const std::complex<double> a_x_amplitude =
      -(kStiffness * oracle.x_m + damping * oracle.v_m_per_s) / kMass;
  FrfError e;
  for (std::size_t n = 0; n < count; ++n) {
    const std::complex<double> turn = phasor(w, n, dt_s);
    e.x = std::max(e.x, std::fabs(trace.x_r_m[n] - (oracle.x_m * turn).real()));
    e.v = std::max(e.v, std::fabs(trace.v_r_m_per_s[n] - (oracle.v_m_per_s * turn).real()));
    e.a_x = std::max(e.a_x, std::fabs(trace.a_x_m_per_s2[n] - (a_x_amplitude * turn).real()));
    CHECK_EQUAL(0, trace.stuck[n]);
  }
  e.x /= std::abs(oracle.x_m);
  e.v /= std::abs(oracle.v_m_per_s);
  e.a_x /= std::abs(a_x_amplitude);
  CHECK_EQUAL(0u, trace.events);
  return e;
}

// --- Coulomb motion under a constant base acceleration (free decay: a_u = 0) ---------------------
struct ChainError {
  double stop_time_relative = 0.0;
  double stop_position_m = 0.0;
  double trajectory_m = 0.0;
  double velocity_m_per_s = 0.0;
};

// Runs the reference for `duration` from (x0, 0) under constant a_u and compares it with the chain
// of half cycles of oracles.hpp: the stop instant (from the exact stuck time), the stop position,
// the events (count - 1 reversals and one stick) and the state at every sample.
ChainError run_chain(double dt_s, double damping, double kinetic_n, double static_n, double a_u,
                     double x0, double duration_s) {
  const auto chain =
      test::coulomb_half_cycles(kMass, kStiffness, damping, kinetic_n, static_n, a_u, x0);
  CHECK_TEXT(chain.sticks, "test case does not stick");
  CHECK_TEXT(chain.count >= 1, "test case does not move");
  const auto count = static_cast<std::size_t>(std::lround(duration_s / dt_s)) + 1;
  const double total_s = static_cast<double>(count - 1) * dt_s;
  CHECK_TEXT(chain.stop_s < total_s - 10 * dt_s, "test case stops too late");
  const std::vector<double> input(count, a_u);
  const ReferenceTrace trace = solve_reference(
      seat(FrictionModel::stick_slip, dt_s, damping, kinetic_n, static_n), input, x0, 0.0);
  ChainError e;
  e.stop_time_relative = std::fabs((total_s - trace.stuck_time_s) - chain.stop_s) / chain.stop_s;
  LONGS_EQUAL(chain.count, static_cast<long>(trace.events));
  const double velocity_scale = std::fabs(x0 - chain.cycle[0].x_equilibrium_m) * chain.omega0;
  for (std::size_t n = 0; n < count; ++n) {
    const double t = static_cast<double>(n) * dt_s;
    double x = 0.0, v = 0.0;
    chain.state_at(t, x, v);
    e.trajectory_m = std::max(e.trajectory_m, std::fabs(trace.x_r_m[n] - x));
    e.velocity_m_per_s = std::max(e.velocity_m_per_s, std::fabs(trace.v_r_m_per_s[n] - v));
    if (t > chain.stop_s) {
      // Stuck for good: exactly at rest, moving with the floor, holding F_L.
      CHECK_EQUAL(1, trace.stuck[n]);
      CHECK_EQUAL(0.0, trace.v_r_m_per_s[n]);
      CHECK(test::same_bits(trace.x_r_m[n], trace.x_r_m[count - 1]));
      CHECK(test::same_bits(a_u, trace.a_x_m_per_s2[n]));
      DOUBLES_EQUAL(-(kMass * a_u + kStiffness * trace.x_r_m[n]), trace.friction_n[n],
                    1e-13 * kMass * (std::fabs(a_u) + 1.0));
    } else if (n > 0 && t < chain.stop_s) {
      CHECK_EQUAL(0, trace.stuck[n]);
    }
  }
  e.stop_position_m = std::fabs(trace.x_r_m[count - 1] - chain.stop_x_m);
  e.velocity_m_per_s /= velocity_scale;
  return e;
}

// --- per-interval events -------------------------------------------------------------------------
// The input of `coarse` linearly interpolated onto a grid `ratio` times finer: the same FOH a_u(t).
std::vector<double> refine(const std::vector<double>& coarse, std::size_t ratio) {
  std::vector<double> fine((coarse.size() - 1) * ratio + 1);
  for (std::size_t j = 0; j < fine.size(); ++j) fine[j] = test::refine_linear(coarse, j, ratio);
  return fine;
}

// Band-limited multi-sine a_u(t) = sum A_i sin(2 pi f_i t + phi_i), sampled at dt.
std::vector<double> multisine(double dt_s, std::size_t count, double rms, std::uint64_t seed) {
  const test::LorrySignal s = test::make_lorry_signal(seed, rms);
  return s.sample(dt_s, count);
}

}  // namespace

// -------------------------------------------------------------------------------------------------
TEST_GROUP(ReferenceLinearFrequencyResponse){};

// Under-, un-, critically and over-damped seats (the last one 40 times critical: its slow mode
// amplifies any coefficient error ~7000 times in the steady state), 0.5-20 Hz, dt = 0.1, 1 and
// 10 ms, and 135 ms at the lower frequencies: at every sample x, v and a_x equal the FOH steady
// state to 1e-12 of their amplitude.
TEST(ReferenceLinearFrequencyResponse, EverySampleIsTheFirstOrderHoldSteadyState) {
  const double dampings[] = {test::kDampingNsPerM, 0.0, kCriticalDamping, 1.7 * kCriticalDamping,
                             40.0 * kCriticalDamping};
  const double frequencies_hz[] = {0.5, 1.8, 5.0, 20.0};
  const double steps_s[] = {1e-4, 1e-3, 1e-2};
  double worst = 0.0;
  for (double damping : dampings) {
    for (double dt : steps_s) {
      for (double f : frequencies_hz) {
        const FrfError e = run_frf(f, dt, damping, dt < 1e-3 ? 1.0 : 10.0);
        const double error = std::max({e.x, e.v, e.a_x});
        CHECK_TEXT(error < 1e-12,
                   StringFromFormat("b = %g, dt = %g, f = %g Hz: %.3e", damping, dt, f, error)
                       .asCharString());
        worst = std::max(worst, error);
      }
    }
  }
  // Coarse steps (omega0 dt = 1.54): the closed form's long-interval branches.
  for (double damping : dampings) {
    for (double f : {0.5, 1.8}) {
      const FrfError e = run_frf(f, 0.135, damping, 60.0);
      const double error = std::max({e.x, e.v, e.a_x});
      CHECK_TEXT(error < 1e-12,
                 StringFromFormat("b = %g, dt = 0.135, f = %g Hz: %.3e", damping, f, error)
                     .asCharString());
      worst = std::max(worst, error);
    }
  }
  test::note_margin("reference FRF worst relative error", worst, 1e-12);
}

// The hold is what the solver integrates: at 20 Hz, dt = 10 ms the continuous H(i w) differs from
// the FOH steady state by ~3 %, so the 1e-12 match above cannot come from a different input model.
TEST(ReferenceLinearFrequencyResponse, TheHoldMattersAtTheTestedFrequencies) {
  const double w = 2.0 * kPi * 20.0;
  const auto foh = test::foh_phasor_response(kMass, test::kDampingNsPerM, kStiffness, w, 1e-2);
  const auto continuous = test::seat_frf(kMass, test::kDampingNsPerM, kStiffness, w);
  CHECK(std::abs(foh.x_m - continuous) / std::abs(continuous) > 1e-2);
}

// -------------------------------------------------------------------------------------------------
TEST_GROUP(ReferenceCoulombFreeDecay){};

// b = 0, a_u = 0, released from x0: the amplitude drops by 2 F_fk/k every half period pi/omega0
// and the seat stops at the first turning point with k|x| <= F_fs. Stop instant to 1e-12
// relative, stop position and trajectory to 1e-12 m, one event per half cycle.
TEST(ReferenceCoulombFreeDecay, UndampedStopsAtTheDenHartogTurningPoint) {
  struct Case {
    double x0, kinetic, static_n, dt;
  };
  const Case cases[] = {{0.05, 40.0, 40.0, 1e-3},   {-0.0317, 40.0, 40.0, 1e-3},
                        {0.2, 40.0, 40.0, 1e-3},    {0.05, 40.0, 60.0, 1e-3},
                        {0.0123, 40.0, 60.0, 1e-3}, {0.05, 40.0, 40.0, 0.1},
                        {-0.12, 40.0, 50.0, 0.0173}};
  ChainError worst;
  for (const Case& c : cases) {
    const auto chain =
        test::coulomb_half_cycles(kMass, kStiffness, 0.0, c.kinetic, c.static_n, 0.0, c.x0);
    const ChainError e =
        run_chain(c.dt, 0.0, c.kinetic, c.static_n, 0.0, c.x0, chain.stop_s + 20.0 * c.dt + 0.5);
    // Den Hartog's turning points, independently of the chain: x_n = (-1)^n sgn(x0) (|x0| -
    // 2 n F_fk/k) (the last one may lie on the same side as the one before).
    const double sign = (chain.count % 2 == 0 ? 1.0 : -1.0) * (c.x0 > 0.0 ? 1.0 : -1.0);
    const double stop = sign * (std::fabs(c.x0) - 2.0 * chain.count * c.kinetic / kStiffness);
    DOUBLES_EQUAL(stop, chain.stop_x_m, 1e-15);
    DOUBLES_EQUAL(chain.count * kPi / std::sqrt(kStiffness / kMass), chain.stop_s, 1e-12);
    CHECK(e.stop_time_relative < 1e-12);
    CHECK(e.stop_position_m < 1e-12);
    CHECK(e.trajectory_m < 1e-12);
    CHECK(e.velocity_m_per_s < 1e-12);
    worst.stop_time_relative = std::max(worst.stop_time_relative, e.stop_time_relative);
    worst.stop_position_m = std::max(worst.stop_position_m, e.stop_position_m);
    worst.trajectory_m = std::max(worst.trajectory_m, e.trajectory_m);
    worst.velocity_m_per_s = std::max(worst.velocity_m_per_s, e.velocity_m_per_s);
  }
  test::note_margin("free decay stop time (relative)", worst.stop_time_relative, 1e-12);
  test::note_margin("free decay stop position (m)", worst.stop_position_m, 1e-12);
  test::note_margin("free decay trajectory (m)", worst.trajectory_m, 1e-12);
  test::note_margin("free decay velocity (relative)", worst.velocity_m_per_s, 1e-12);
}

// With viscous damping each half cycle lasts pi/omega_d and the excursion about the shifted
// equilibrium shrinks by exp(-sigma pi/omega_d).
TEST(ReferenceCoulombFreeDecay, DampedStopsWhereTheHalfCycleChainStops) {
  const double x0s[] = {0.08, -0.05};
  ChainError worst;
  for (double x0 : x0s) {
    const auto chain =
        test::coulomb_half_cycles(kMass, kStiffness, test::kDampingNsPerM, 20.0, 24.0, 0.0, x0);
    CHECK(chain.count >= 3);
    const ChainError e =
        run_chain(1e-3, test::kDampingNsPerM, 20.0, 24.0, 0.0, x0, chain.stop_s + 0.5);
    CHECK(e.stop_time_relative < 1e-12);
    CHECK(e.stop_position_m < 1e-12);
    CHECK(e.trajectory_m < 1e-12);
    CHECK(e.velocity_m_per_s < 1e-12);
    worst.stop_time_relative = std::max(worst.stop_time_relative, e.stop_time_relative);
    worst.stop_position_m = std::max(worst.stop_position_m, e.stop_position_m);
    worst.trajectory_m = std::max(worst.trajectory_m, e.trajectory_m);
  }
  test::note_margin("damped decay stop time (relative)", worst.stop_time_relative, 1e-12);
  test::note_margin("damped decay stop position (m)", worst.stop_position_m, 1e-12);
  test::note_margin("damped decay trajectory (m)", worst.trajectory_m, 1e-12);
}

// -------------------------------------------------------------------------------------------------
TEST_GROUP(ReferenceConstantBaseAcceleration){};

// |m a_u| <= F_fs from rest: the seat never moves, bit for bit, and is stuck the whole time.
TEST(ReferenceConstantBaseAcceleration, BelowBreakAwayNothingMovesBitForBit) {
  const double accelerations[] = {0.3, -0.45, 0.0, 0.999 * 45.0 / kMass};
  for (double a_u : accelerations) {
    const std::vector<double> input(5001, a_u);
    for (FrictionModel model :
         {FrictionModel::stick_slip, FrictionModel::stribeck, FrictionModel::signum}) {
      OscillatorParams p = seat(model, 1e-3, test::kDampingNsPerM, 40.0, 45.0);
      if (model == FrictionModel::signum) p.kinetic_friction_n = 45.0;
      const ReferenceTrace trace = solve_reference(p, input);
      for (std::size_t n = 0; n < input.size(); ++n) {
        CHECK(test::same_bits(0.0, trace.x_r_m[n]));
        CHECK(test::same_bits(0.0, trace.v_r_m_per_s[n]));
        CHECK(test::same_bits(a_u, trace.a_x_m_per_s2[n]));
        CHECK_EQUAL(1, trace.stuck[n]);
        DOUBLES_EQUAL(-kMass * a_u, trace.friction_n[n], 1e-15 * kMass);
      }
      CHECK_EQUAL(0u, trace.events);
      DOUBLES_EQUAL(5.0, trace.stuck_time_s, 1e-14);
    }
  }
}

// |m a_u| > F_fs from rest: it slips at once, stops for good after the half cycle pi/omega_d at
// x_e (1 + e^{-sigma pi/omega_d}), x_e = -(m a_u + F_fk d)/k, when |F_L| <= F_fs there.
TEST(ReferenceConstantBaseAcceleration, AboveBreakAwayFirstStickIsAtHalfTheDampedPeriod) {
  struct Case {
    double damping, a_u;
  };
  const double kinetic = 40.0, static_n = 48.0;
  const Case cases[] = {{0.0, 60.0 / kMass},
                        {0.0, -60.0 / kMass},
                        {test::kDampingNsPerM, 55.0 / kMass},
                        {test::kDampingNsPerM, -80.0 / kMass}};
  ChainError worst;
  for (const Case& c : cases) {
    const double sigma = c.damping / (2.0 * kMass);
    const double omega_d = std::sqrt(kStiffness / kMass - sigma * sigma);
    const double d = -c.a_u > 0.0 ? 1.0 : -1.0;
    const double x_e = -(kMass * c.a_u + kinetic * d) / kStiffness;
    const double x_stop = x_e * (1.0 + std::exp(-sigma * kPi / omega_d));
    const auto chain =
        test::coulomb_half_cycles(kMass, kStiffness, c.damping, kinetic, static_n, c.a_u, 0.0);
    LONGS_EQUAL(1, chain.count);  // one half cycle, then stuck
    DOUBLES_EQUAL(kPi / omega_d, chain.stop_s, 1e-15);
    DOUBLES_EQUAL(x_stop, chain.stop_x_m, 1e-17);
    const ChainError e = run_chain(1e-3, c.damping, kinetic, static_n, c.a_u, 0.0, 1.0);
    CHECK(e.stop_time_relative < 1e-12);
    CHECK(e.stop_position_m < 1e-12);
    CHECK(e.trajectory_m < 1e-12);
    worst.stop_time_relative = std::max(worst.stop_time_relative, e.stop_time_relative);
    worst.stop_position_m = std::max(worst.stop_position_m, e.stop_position_m);
    worst.trajectory_m = std::max(worst.trajectory_m, e.trajectory_m);
  }
  test::note_margin("constant input stop time (relative)", worst.stop_time_relative, 1e-12);
  test::note_margin("constant input stop position (m)", worst.stop_position_m, 1e-12);
  test::note_margin("constant input trajectory (m)", worst.trajectory_m, 1e-12);
}

// -------------------------------------------------------------------------------------------------
TEST_GROUP(ReferenceEventsInsideSampleIntervals){};

// The same FOH a_u(t) sampled at dt = 60 ms (omega0 dt = 0.69: stick, break-away and reversal
// often share one interval) and 50 times finer: at the common instants the two runs agree to
// 1e-12, with the same events and stuck time. The coarse run must therefore find every event
// inside its intervals, including v_r returning to 0 after an event in the same interval, which
// the sign of v_r at the interval ends cannot show. (Evidence that such intervals occur: intervals
// with two or more events, counted by running the coarse scene interval by interval. These scenes
// also take the solver's dip branch - |v_r| falling to 0 inside a slip piece whose ends have the
// same sign - 8 times, as an instrumented solver counts.)
TEST(ReferenceEventsInsideSampleIntervals, CoarseSamplingMatchesFineSamplingOfTheSameInput) {
  const double dt = 0.06;
  const std::size_t ratio = 50, count = 501;  // 30 s
  double worst_x = 0.0, worst_v = 0.0, worst_p = 0.0;
  int intervals_with_several_events = 0;
  struct Scene {
    double damping, kinetic, static_n, rms;
    std::uint64_t seed;
  };
  const Scene scenes[] = {{test::kDampingNsPerM, 30.0, 36.0, 1.2, 7},
                          {0.0, 25.0, 25.0, 0.8, 11},
                          {test::kDampingNsPerM, 40.0, 40.0, 2.5, 5}};
  for (const Scene& s : scenes) {
    const std::vector<double> coarse = multisine(dt, count, s.rms, s.seed);
    const std::vector<double> fine = refine(coarse, ratio);
    const OscillatorParams pc =
        seat(FrictionModel::stick_slip, dt, s.damping, s.kinetic, s.static_n);
    OscillatorParams pf = pc;
    pf.dt_s = dt / static_cast<double>(ratio);
    const ReferenceTrace c = solve_reference(pc, coarse);
    const ReferenceTrace f = solve_reference(pf, fine);
    double x_scale = 0.0, v_scale = 0.0;
    for (std::size_t n = 0; n < count; ++n) {
      x_scale = std::max(x_scale, std::fabs(c.x_r_m[n]));
      v_scale = std::max(v_scale, std::fabs(c.v_r_m_per_s[n]));
    }
    double ex = 0.0, ev = 0.0;
    for (std::size_t n = 0; n < count; ++n) {
      ex = std::max(ex, std::fabs(c.x_r_m[n] - f.x_r_m[n * ratio]));
      ev = std::max(ev, std::fabs(c.v_r_m_per_s[n] - f.v_r_m_per_s[n * ratio]));
      CHECK_EQUAL(f.stuck[n * ratio], c.stuck[n]);
    }
    CHECK(c.events > 100);
    LONGS_EQUAL(static_cast<long>(f.events), static_cast<long>(c.events));
    const double p_error = std::fabs(c.stuck_time_s - f.stuck_time_s) / (dt * (count - 1));
    CHECK(ex / x_scale < 1e-12);
    CHECK(ev / v_scale < 1e-12);
    CHECK(p_error < 1e-12);
    worst_x = std::max(worst_x, ex / x_scale);
    worst_v = std::max(worst_v, ev / v_scale);
    worst_p = std::max(worst_p, p_error);

    // Events per coarse interval, from two-sample runs chained through the coarse states.
    std::uint64_t total = 0;
    for (std::size_t n = 1; n < count; ++n) {
      const ReferenceTrace step =
          solve_reference(pc, {coarse[n - 1], coarse[n]}, c.x_r_m[n - 1], c.v_r_m_per_s[n - 1]);
      total += step.events;
      if (step.events >= 2) ++intervals_with_several_events;
    }
    LONGS_EQUAL(static_cast<long>(c.events), static_cast<long>(total));
  }
  CHECK(intervals_with_several_events > 10);
  test::note_margin("coarse vs fine x (relative)", worst_x, 1e-12);
  test::note_margin("coarse vs fine v (relative)", worst_v, 1e-12);
  test::note_margin("coarse vs fine p", worst_p, 1e-12);
  test::note_margin("intervals with >= 2 events", intervals_with_several_events, 10);
}

// -------------------------------------------------------------------------------------------------
TEST_GROUP(ReferenceSolverParameters){};

// The core's validation, with the exact integrator whatever params.integrator says.
TEST(ReferenceSolverParameters, RefusesWhatTheCoreRefusesNamingTheParameter) {
  const std::vector<double> input(10, 0.1);
  struct Bad {
    OscillatorParams params;
    const char* parameter;
  };
  OscillatorParams mass = seat(FrictionModel::stick_slip, 1e-3, 504.0, 40.0, 45.0);
  mass.mass_kg = -1.0;
  OscillatorParams below = seat(FrictionModel::stick_slip, 1e-3, 504.0, 40.0, 30.0);
  OscillatorParams coarse =
      seat(FrictionModel::stick_slip, 0.2, 504.0, 40.0, 45.0);  // omega0 dt > pi/2
  coarse.integrator = Integrator::rk4;
  OscillatorParams stribeck = seat(FrictionModel::stribeck, 1e-3, 504.0, 40.0, 45.0);
  stribeck.stribeck_velocity_m_per_s = 0.0;
  OscillatorParams nan_damping = seat(FrictionModel::linear, 1e-3, std::nan(""));
  const Bad cases[] = {{mass, "mass_kg"},
                       {below, "static_friction_n"},
                       {coarse, "dt_s"},
                       {stribeck, "stribeck_velocity_m_per_s"},
                       {nan_damping, "damping_ns_per_m"}};
  for (const Bad& bad : cases) {
    std::string message;
    try {
      solve_reference(bad.params, input);
    } catch (const ConfigurationError& error) {
      message = error.what();
    }
    STRCMP_CONTAINS(bad.parameter, message.c_str());
  }
}

TEST(ReferenceSolverParameters, RefusesAnEmptyOrNonFiniteInputAndInitialState) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 1e-3, 504.0, 40.0, 45.0);
  const auto refused = [&](const std::vector<double>& input, double x0, double v0) {
    try {
      solve_reference(p, input, x0, v0);
    } catch (const HostError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  STRCMP_CONTAINS("no samples", refused({}, 0.0, 0.0).c_str());
  STRCMP_CONTAINS("a_u[2]", refused({0.0, 1.0, std::nan(""), 0.0}, 0.0, 0.0).c_str());
  STRCMP_CONTAINS("not finite", refused({0.0, 1.0}, HUGE_VAL, 0.0).c_str());
  // A single sample is the initial state alone.
  const ReferenceTrace one = solve_reference(p, {0.2}, 0.001, 0.0);
  LONGS_EQUAL(1, static_cast<long>(one.x_r_m.size()));
  CHECK(test::same_bits(0.001, one.x_r_m[0]));
}

// Initial state: stuck iff v0 = 0 and |F_L(0)| <= F_fs; otherwise slipping with v0's sign (or
// F_L's); the first row reports the friction and a_x of that state.
TEST(ReferenceSolverParameters, InitialStateFollowsTheStickLogic) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 1e-3, 504.0, 40.0, 45.0);
  const ReferenceTrace stuck = solve_reference(p, {0.1, 0.1}, 0.002, 0.0);  // F_L = -31.8 N
  CHECK_EQUAL(1, stuck.stuck[0]);
  DOUBLES_EQUAL(-(kMass * 0.1 + kStiffness * 0.002), stuck.friction_n[0], 1e-12);
  CHECK(test::same_bits(0.1, stuck.a_x_m_per_s2[0]));
  const ReferenceTrace breaking = solve_reference(p, {0.1, 0.1}, 0.005, 0.0);  // F_L = -66.3 N
  CHECK_EQUAL(0, breaking.stuck[0]);
  DOUBLES_EQUAL(-40.0, breaking.friction_n[0], 0.0);
  DOUBLES_EQUAL(-(kStiffness * 0.005 - 40.0) / kMass, breaking.a_x_m_per_s2[0], 1e-14);
  CHECK(breaking.v_r_m_per_s[1] < 0.0);  // moves towards the load
  const ReferenceTrace moving = solve_reference(p, {0.1, 0.1}, 0.0, 0.01);
  DOUBLES_EQUAL(40.0, moving.friction_n[0], 0.0);
}
