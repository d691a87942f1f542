// Free decay of the undamped seat with Coulomb stick-slip friction (no input, exact integrator).
//
// Closed form (Den Hartog): with b = 0 each half cycle is half a period pi/omega0 of an undamped
// oscillation about x_e = +-F_fk/k, so the turning points are
//   x_n = (-1)^n sgn(x0) (|x0| - 2 n F_fk/k),   t_n = n pi/omega0,
// and the motion stops at the first turning point with k |x_n| <= F_fs.
#include <algorithm>
#include <cmath>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

constexpr double kKineticN = 40.0;
constexpr double kPositionTolerance = 1e-9;  // m
constexpr double kTimeTolerance = 1e-9;      // s

struct DecayCase {
  double x0_m;
  double static_n;
};

struct TurningPoints {
  int stop_index = 0;  // n of the turning point where it sticks
  double omega0 = 0.0;
  double position(int n) const { return x_at[n]; }
  double x_at[512];
};

// The closed form above, written independently of the chained oracle in oracles.hpp.
TurningPoints den_hartog_turning_points(double x0, double static_n) {
  TurningPoints tp;
  tp.omega0 = std::sqrt(test::kStiffnessNPerM / test::kMassKg);
  const double delta = kKineticN / test::kStiffnessNPerM;
  const double sign0 = x0 > 0.0 ? 1.0 : -1.0;
  for (int n = 0; n < 512; ++n) {
    const double amplitude = std::fabs(x0) - 2.0 * n * delta;
    tp.x_at[n] = (n % 2 == 0 ? 1.0 : -1.0) * sign0 * amplitude;
    const double spring = test::kStiffnessNPerM * std::fabs(tp.x_at[n]);
    // A case right at the threshold would test rounding, not physics: the cases avoid it.
    CHECK_TEXT(std::fabs(spring - static_n) > 1e-6, "ambiguous test case: k|x_n| == F_fs");
    if (spring <= static_n) {
      tp.stop_index = n;
      return tp;
    }
  }
  FAIL("test case does not stop within 512 half cycles");
  return tp;
}

OscillatorParams decay_params(double dt_s, double static_n) {
  OscillatorParams p =
      test::reference_params(FrictionModel::stick_slip, Integrator::exact, dt_s, 0.0);
  p.kinetic_friction_n = kKineticN;
  p.static_friction_n = static_n;
  return p;
}

struct DecayRun {
  double stop_time_error_s = 0.0;
  double stop_position_error_m = 0.0;
  double reversal_time_error_s = 0.0;
  double reversal_position_error_m = 0.0;
  double trajectory_error_m = 0.0;
  int reversals_seen = 0;
};

DecayRun run_decay(const DecayCase& c, double dt) {
  const TurningPoints tp = den_hartog_turning_points(c.x0_m, c.static_n);
  const auto chain = test::coulomb_half_cycles(test::kMassKg, test::kStiffnessNPerM, 0.0, kKineticN,
                                               c.static_n, 0.0, c.x0_m);
  CHECK(chain.sticks);
  LONGS_EQUAL(tp.stop_index, chain.count);

  Oscillator<double, CoulombStickSlip> seat;
  const auto config = seat.configure(decay_params(dt, c.static_n));
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(c.x0_m, 0.0, 0.0);
  CHECK_FALSE(seat.current().stuck);

  const double omega0 = tp.omega0;
  const double half_period = kPi / omega0;
  const double stop_time = tp.stop_index * half_period;
  DecayRun r;
  bool stopped = false;
  const long last_step = static_cast<long>(stop_time / dt) + 200;
  for (long j = 1; j <= last_step; ++j) {
    const auto out = seat.step(0.0);
    const double t = static_cast<double>(j) * dt;
    if (!stopped && out.stuck) {
      stopped = true;
      CHECK(out.stuck_time_s >= 0.0 && out.stuck_time_s <= dt);
      r.stop_time_error_s = std::fabs((t - out.stuck_time_s) - stop_time);
      r.stop_position_error_m = std::fabs(out.x_r_m - tp.position(tp.stop_index));
    } else if (stopped) {
      // Once stuck with no input it stays stuck, exactly where it stopped.
      CHECK(out.stuck);
      CHECK_EQUAL(0.0, out.v_r_m_per_s);
      DOUBLES_EQUAL(tp.position(tp.stop_index), out.x_r_m, kPositionTolerance);
      DOUBLES_EQUAL(dt, out.stuck_time_s, 0.0);
      continue;
    }
    if (!out.stuck) CHECK_EQUAL(0.0, out.stuck_time_s);
    double x_expected = 0.0, v_expected = 0.0;
    chain.state_at(t, x_expected, v_expected);
    r.trajectory_error_m = std::max(r.trajectory_error_m, std::fabs(out.x_r_m - x_expected));
    if (out.events > 0 && !out.stuck) {
      // A reversal in this step: recover the turning point and its instant from the end state on
      // the circle of the new half cycle, (x - x_e)^2 + (v/omega0)^2 = R^2.
      const int n = ++r.reversals_seen;
      CHECK_TEXT(n < tp.stop_index, "more reversals than the closed form");
      if (n >= tp.stop_index) break;
      const double d = n % 2 == 0 ? (c.x0_m > 0.0 ? -1.0 : 1.0) : (c.x0_m > 0.0 ? 1.0 : -1.0);
      const double x_e = -kKineticN * d / test::kStiffnessNPerM;
      const double y = out.x_r_m - x_e, w = out.v_r_m_per_s / omega0;
      const double radius = std::hypot(y, w);
      const double turning = x_e - d * radius;
      const double since = std::atan2(d * w, -d * y) / omega0;
      r.reversal_position_error_m =
          std::max(r.reversal_position_error_m, std::fabs(turning - tp.position(n)));
      r.reversal_time_error_s =
          std::max(r.reversal_time_error_s, std::fabs((t - since) - n * half_period));
      // And the reversal lies inside this step.
      CHECK(n * half_period > t - dt - kTimeTolerance && n * half_period <= t + kTimeTolerance);
    }
  }
  CHECK_TEXT(stopped, "never stuck");
  LONGS_EQUAL(tp.stop_index - 1, r.reversals_seen);
  CHECK_EQUAL(0u, seat.event_budget_exhausted());
  return r;
}

const double kSteps_s[] = {1e-4, 1e-3, 1e-2, 0.05};
const DecayCase kCases[] = {
    {0.05, kKineticN},          // F_fs = F_fk: stops at the first |x_n| <= F_fk/k
    {-0.0317, kKineticN},       // negative start
    {0.2, kKineticN},           // many half cycles (~28)
    {0.05, 1.5 * kKineticN},    // F_fs > F_fk: stops one turning point earlier
    {0.0123, 1.5 * kKineticN},  // a single half cycle
    {-0.12, 1.25 * kKineticN},
};

}  // namespace

TEST_GROUP(CoulombFreeDecay){};

// The central claim: stop instant and stop position to 1e-9 whatever dt (events located inside
// the step), for F_fs = F_fk and F_fs > F_fk.
TEST(CoulombFreeDecay, StopsAtFirstTurningPointWithinStaticFriction) {
  double worst_time = 0.0, worst_position = 0.0;
  for (double dt : kSteps_s) {
    for (const DecayCase& c : kCases) {
      const DecayRun r = run_decay(c, dt);
      const SimpleString where =
          StringFromFormat("x0 = %g m, F_fs = %g N, dt = %g s", c.x0_m, c.static_n, dt);
      CHECK_TEXT(
          r.stop_time_error_s < kTimeTolerance,
          StringFromFormat("%s: stop time error %.3e s", where.asCharString(), r.stop_time_error_s)
              .asCharString());
      CHECK_TEXT(r.stop_position_error_m < kPositionTolerance,
                 StringFromFormat("%s: stop position error %.3e m", where.asCharString(),
                                  r.stop_position_error_m)
                     .asCharString());
      worst_time = std::max(worst_time, r.stop_time_error_s);
      worst_position = std::max(worst_position, r.stop_position_error_m);
    }
  }
  test::note_margin("stop time error, s", worst_time, kTimeTolerance);
  test::note_margin("stop position error, m", worst_position, kPositionTolerance);
}

// Every reversal: turning point |x_n| = |x0| - 2 n F_fk/k (so 4 F_fk/k per cycle) at n pi/omega0,
// and the whole trajectory in between on the piecewise cosine.
TEST(CoulombFreeDecay, ReversalsLoseTwoFrictionDisplacementsEveryHalfPeriod) {
  double worst_time = 0.0, worst_position = 0.0, worst_trajectory = 0.0;
  for (double dt : kSteps_s) {
    for (const DecayCase& c : kCases) {
      const DecayRun r = run_decay(c, dt);
      const SimpleString where =
          StringFromFormat("x0 = %g m, F_fs = %g N, dt = %g s", c.x0_m, c.static_n, dt);
      CHECK_TEXT(r.reversal_time_error_s < kTimeTolerance,
                 StringFromFormat("%s: reversal time error %.3e s", where.asCharString(),
                                  r.reversal_time_error_s)
                     .asCharString());
      CHECK_TEXT(r.reversal_position_error_m < kPositionTolerance,
                 StringFromFormat("%s: turning point error %.3e m", where.asCharString(),
                                  r.reversal_position_error_m)
                     .asCharString());
      CHECK_TEXT(r.trajectory_error_m < kPositionTolerance,
                 StringFromFormat("%s: trajectory error %.3e m", where.asCharString(),
                                  r.trajectory_error_m)
                     .asCharString());
      worst_time = std::max(worst_time, r.reversal_time_error_s);
      worst_position = std::max(worst_position, r.reversal_position_error_m);
      worst_trajectory = std::max(worst_trajectory, r.trajectory_error_m);
    }
  }
  test::note_margin("reversal time error, s", worst_time, kTimeTolerance);
  test::note_margin("turning point error, m", worst_position, kPositionTolerance);
  test::note_margin("trajectory error, m", worst_trajectory, kPositionTolerance);
}

// The two oracles (the Den Hartog turning points and the chained half cycles) agree: guards the
// test's own closed forms.
TEST(CoulombFreeDecay, ChainedHalfCyclesReproduceDenHartogDecrement) {
  for (const DecayCase& c : kCases) {
    const TurningPoints tp = den_hartog_turning_points(c.x0_m, c.static_n);
    const auto chain = test::coulomb_half_cycles(test::kMassKg, test::kStiffnessNPerM, 0.0,
                                                 kKineticN, c.static_n, 0.0, c.x0_m);
    LONGS_EQUAL(tp.stop_index, chain.count);
    for (int n = 0; n < chain.count; ++n) {
      DOUBLES_EQUAL(tp.position(n), chain.cycle[n].x_start_m, 1e-15);
      DOUBLES_EQUAL(n * kPi / tp.omega0, chain.cycle[n].start_s, 1e-13);
    }
    DOUBLES_EQUAL(tp.position(tp.stop_index), chain.stop_x_m, 1e-15);
  }
}

// Released with |k x0| <= F_fs the seat never moves: stuck from the first step, x unchanged.
TEST(CoulombFreeDecay, ReleasedWithinStaticFrictionNeverMoves) {
  for (double dt : kSteps_s) {
    Oscillator<double, CoulombStickSlip> seat;
    const auto config = seat.configure(decay_params(dt, 1.5 * kKineticN));
    CHECK_TEXT(config.ok(), config.message.c_str());
    const double x0 = 0.99 * 1.5 * kKineticN / test::kStiffnessNPerM;
    seat.reset(x0, 0.0, 0.0);
    CHECK(seat.current().stuck);
    for (int j = 0; j < 1000; ++j) {
      const auto out = seat.step(0.0);
      CHECK(out.stuck);
      CHECK_EQUAL(x0, out.x_r_m);
      CHECK_EQUAL(0.0, out.v_r_m_per_s);
      CHECK_EQUAL(0.0, out.a_x_m_per_s2);
      LONGS_EQUAL(0, out.events);
    }
  }
}
