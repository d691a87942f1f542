// Stick-slip seat under a constant cab-floor acceleration a_u, released at rest.
//
// Below break-away (|m a_u| <= F_fs) nothing may move at all: the stuck branch must be exact, not
// merely accurate. Above, the seat slips from t = 0 and, the friction being the constant F_fk d,
// obeys the linear ODE m x'' + b x' + k x = -(m a_u + F_fk d): a damped oscillation about
//   x_e = -(m a_u + F_fk d)/k,   x(t) = x_e [1 - e^{-sigma t}(cos w_d t + sigma/w_d sin w_d t)],
// whose velocity first returns to 0 at t = pi/w_d, at x = x_e (1 + e^{-sigma pi/w_d}). It sticks
// there if |F_L| = |m a_u + k x| <= F_fs, otherwise it reverses and the same holds per half cycle.
#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

constexpr double kKineticN = 40.0;
constexpr double kStaticN = 50.0;
constexpr double kPositionTolerance = 1e-9;  // m
constexpr double kTimeTolerance = 1e-9;      // s

const Integrator kAllIntegrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                      Integrator::exact};

OscillatorParams sticking_params(FrictionModel model, Integrator integrator, double dt_s,
                                 double damping = test::kDampingNsPerM) {
  OscillatorParams p = test::reference_params(model, integrator, dt_s, damping);
  p.kinetic_friction_n = kKineticN;
  p.static_friction_n = kStaticN;
  p.stribeck_velocity_m_per_s = 0.01;
  return p;
}

// Holds a_u constant for `steps` and requires the seat to be stuck at rest, bit for bit.
template <typename T, typename Law>
void check_never_moves(Integrator integrator, double a_u_double, bool ramp_in) {
  Oscillator<T, Law> seat;
  const auto config = seat.configure(sticking_params(Law::model, integrator, 1e-3));
  CHECK_TEXT(config.ok(), config.message.c_str());
  const T a_u = static_cast<T>(a_u_double);
  // Released with the input already there, or ramped in over the first step by the hold.
  seat.reset(T(0), T(0), ramp_in ? T(0) : a_u);
  CHECK(seat.current().stuck);
  const T holding =
      -(static_cast<T>(test::kMassKg) * a_u + static_cast<T>(test::kStiffnessNPerM) * T(0));
  for (int j = 0; j < 20000; ++j) {
    const auto out = seat.step(a_u);
    CHECK(out.stuck);
    CHECK(out.x_r_m == T(0));
    CHECK(out.v_r_m_per_s == T(0));
    CHECK(test::same_bits(out.a_x_m_per_s2, a_u));  // moves with the floor, bit for bit
    CHECK(out.friction_n == holding);
    CHECK(out.stuck_time_s == seat.dt_s());
    LONGS_EQUAL(0, out.events);
  }
  CHECK_EQUAL(0u, seat.event_budget_exhausted());
}

struct SlipRun {
  double stick_time_error_s = 0.0;
  double stick_position_error_m = 0.0;
  double trajectory_error_m = 0.0;
  double acceleration_error_m_per_s2 = 0.0;
};

// Released at rest above break-away with the input already applied; compares against the chained
// closed form until it sticks, then checks it stays stuck.
SlipRun run_slip(double a_u, double damping, double dt, int expected_half_cycles) {
  const auto chain = test::coulomb_half_cycles(test::kMassKg, test::kStiffnessNPerM, damping,
                                               kKineticN, kStaticN, a_u, 0.0);
  CHECK(chain.sticks);
  LONGS_EQUAL(expected_half_cycles, chain.count);
  // The case must not sit on the threshold |F_L| = F_fs at the stop.
  const double limit_at_stop = -(test::kMassKg * a_u + test::kStiffnessNPerM * chain.stop_x_m);
  CHECK(std::fabs(std::fabs(limit_at_stop) - kStaticN) > 1e-3);

  Oscillator<double, CoulombStickSlip> seat;
  const auto config =
      seat.configure(sticking_params(FrictionModel::stick_slip, Integrator::exact, dt, damping));
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(0.0, 0.0, a_u);
  CHECK_FALSE(seat.current().stuck);  // |m a_u| > F_fs: slipping from t = 0

  SlipRun r;
  bool stuck = false;
  const long steps = static_cast<long>(chain.stop_s / dt) + 100;
  for (long j = 1; j <= steps; ++j) {
    const auto out = seat.step(a_u);
    const double t = static_cast<double>(j) * dt;
    if (j == 1) {
      CHECK_EQUAL(0.0, out.stuck_time_s);  // no stuck time at all: it broke away at t = 0
    }
    if (!stuck && out.stuck) {
      stuck = true;
      r.stick_time_error_s = std::fabs((t - out.stuck_time_s) - chain.stop_s);
      r.stick_position_error_m = std::fabs(out.x_r_m - chain.stop_x_m);
    } else if (stuck) {
      CHECK(out.stuck);  // constant input: |F_L| stays below F_fs
      CHECK(test::same_bits(a_u, out.a_x_m_per_s2));
    } else {
      double x = 0.0, v = 0.0;
      chain.state_at(t, x, v);
      r.trajectory_error_m = std::max(r.trajectory_error_m, std::fabs(out.x_r_m - x));
      // a_x from the closed form: -(k x + b v + F_fk d)/m, d of the current half cycle.
      const double d = chain.cycle[chain.half_cycle_at(t)].direction;
      const double a_x = -(test::kStiffnessNPerM * x + damping * v + kKineticN * d) / test::kMassKg;
      r.acceleration_error_m_per_s2 =
          std::max(r.acceleration_error_m_per_s2, std::fabs(out.a_x_m_per_s2 - a_x));
      CHECK(out.friction_n == kKineticN * d);
      CHECK_EQUAL(0.0, out.stuck_time_s);
    }
  }
  CHECK_TEXT(stuck, "never stuck");
  CHECK_EQUAL(0u, seat.event_budget_exhausted());
  return r;
}

void check_slip(const SlipRun& r, const char* what, double a_u, double dt) {
  const SimpleString where = StringFromFormat("%s a_u = %g, dt = %g", what, a_u, dt);
  CHECK_TEXT(
      r.stick_time_error_s < kTimeTolerance,
      StringFromFormat("%s: stick instant error %.3e s", where.asCharString(), r.stick_time_error_s)
          .asCharString());
  CHECK_TEXT(r.stick_position_error_m < kPositionTolerance,
             StringFromFormat("%s: stick position error %.3e m", where.asCharString(),
                              r.stick_position_error_m)
                 .asCharString());
  CHECK_TEXT(
      r.trajectory_error_m < kPositionTolerance,
      StringFromFormat("%s: trajectory error %.3e m", where.asCharString(), r.trajectory_error_m)
          .asCharString());
  // a_x = -(k x + b v + F_fk d)/m inherits k/m ~ 130 1/s^2 times the position error.
  CHECK_TEXT(r.acceleration_error_m_per_s2 < 1e-6,
             StringFromFormat("%s: a_x error %.3e m/s^2", where.asCharString(),
                              r.acceleration_error_m_per_s2)
                 .asCharString());
}

const double kSteps_s[] = {1e-4, 1e-3, 1e-2, 0.05};

}  // namespace

TEST_GROUP(ConstantBaseAcceleration){};

// |m a_u| <= F_fs: x_r = v_r = 0 and a_x = a_u bit for bit, for every integrator, both sticking
// laws, float and double, released with the input or with the input ramped in by the hold.
TEST(ConstantBaseAcceleration, BelowBreakAwayStaysStuckBitForBit) {
  const double inputs[] = {0.0, 0.3, -0.45, 0.999 * kStaticN / test::kMassKg,
                           -0.999 * kStaticN / test::kMassKg};
  for (Integrator integrator : kAllIntegrators) {
    for (double a_u : inputs) {
      for (bool ramp_in : {false, true}) {
        check_never_moves<double, CoulombStickSlip>(integrator, a_u, ramp_in);
        check_never_moves<double, StribeckStickSlip>(integrator, a_u, ramp_in);
        check_never_moves<float, CoulombStickSlip>(integrator, a_u, ramp_in);
        check_never_moves<float, StribeckStickSlip>(integrator, a_u, ramp_in);
      }
    }
  }
}

// Above break-away with b = 504: slips from t = 0 and sticks at t = pi/w_d, x = x_e(1 + e^{-sigma
// pi/w_d}), for both signs of a_u and every dt (the instant lies inside a step).
TEST(ConstantBaseAcceleration, DampedSlipSticksAfterHalfADampedPeriod) {
  double worst_time = 0.0, worst_position = 0.0;
  for (double dt : kSteps_s) {
    for (double a_u : {1.5, -1.5, 0.7, -2.6}) {
      const SlipRun r = run_slip(a_u, test::kDampingNsPerM, dt, 1);
      check_slip(r, "b = 504", a_u, dt);
      worst_time = std::max(worst_time, r.stick_time_error_s);
      worst_position = std::max({worst_position, r.stick_position_error_m, r.trajectory_error_m});
    }
  }
  // The oracle in its simplest form for one case: pi/w_d and x_e (1 + e^{-sigma pi/w_d}).
  const double sigma = test::kDampingNsPerM / (2.0 * test::kMassKg);
  const double wd = std::sqrt(test::kStiffnessNPerM / test::kMassKg - sigma * sigma);
  const double x_e = -(test::kMassKg * 1.5 - kKineticN) / test::kStiffnessNPerM;
  const auto chain = test::coulomb_half_cycles(test::kMassKg, test::kStiffnessNPerM,
                                               test::kDampingNsPerM, kKineticN, kStaticN, 1.5, 0.0);
  DOUBLES_EQUAL(kPi / wd, chain.stop_s, 1e-15);
  DOUBLES_EQUAL(x_e * (1.0 + std::exp(-sigma * kPi / wd)), chain.stop_x_m, 1e-15);
  test::note_margin("damped stick instant error, s", worst_time, kTimeTolerance);
  test::note_margin("damped stick position/trajectory error, m", worst_position,
                    kPositionTolerance);
}

// b = 0: half an undamped period pi/omega0, x = 2 x_e; sticks if m a_u <= F_fs + 2 F_fk.
TEST(ConstantBaseAcceleration, UndampedSlipSticksAfterHalfAPeriodAtTwiceTheShiftedEquilibrium) {
  double worst = 0.0;
  for (double dt : kSteps_s) {
    for (double a_u : {1.0, -1.2, 0.6}) {
      const SlipRun r = run_slip(a_u, 0.0, dt, 1);
      check_slip(r, "b = 0", a_u, dt);
      worst = std::max({worst, r.stick_time_error_s, r.stick_position_error_m});
    }
  }
  test::note_margin("undamped stick instant/position error", worst, kTimeTolerance);
}

// Strong enough input: at the first v_r = 0 the limit force exceeds F_fs, it reverses, and sticks
// at a later half cycle; every instant and turning point from the chained closed form.
TEST(ConstantBaseAcceleration, StrongInputReversesBeforeSticking) {
  double worst = 0.0;
  for (double dt : kSteps_s) {
    const SlipRun damped = run_slip(4.0, test::kDampingNsPerM, dt, 2);
    check_slip(damped, "b = 504 reversing", 4.0, dt);
    const SlipRun undamped = run_slip(-2.6, 0.0, dt, 3);
    check_slip(undamped, "b = 0 reversing", -2.6, dt);
    worst = std::max({worst, damped.stick_time_error_s, damped.stick_position_error_m,
                      undamped.stick_time_error_s, undamped.stick_position_error_m});
  }
  test::note_margin("reversing stick instant/position error", worst, kTimeTolerance);
}
