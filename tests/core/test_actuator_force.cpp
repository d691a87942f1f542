// The actuator force f_a on the seat (Oscillator::step(a_u, f_a)), held over the step it is given
// with, against closed forms, for every scalar:
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u + f_a,   F_L = f_a - (m a_u + k x_r).
// With the floor at rest (a_u = 0) and a constant force F the seat is a damped oscillator about
// x_e = (F - F_f)/k: below break-away (|F| <= F_fs) it never moves and the friction holds F; above
// it slips from t = 0 and first comes to rest at t = pi/w_d, at x_e (1 + e^{-sigma pi/w_d})
// (the free decay of tests/core/test_constant_base_acceleration.cpp with a_u = -F/m). Without
// friction it settles at the static deflection F/k with a_x = 0.
#include <cmath>
#include <cstddef>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_oscillator.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

constexpr double kKineticN = 40.0;
constexpr double kStaticN = 50.0;
constexpr double kDtS = 1e-3;

OscillatorParams seat_params(FrictionModel model) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, kDtS);
  if (model != FrictionModel::linear) {
    p.kinetic_friction_n = kKineticN;
    p.static_friction_n = kStaticN;
  }
  p.displacement_range_m = 0.1;  // the Q7.24 scene's unit of length from the motions below
  p.input_range_m_per_s2 = 5.0;  // covers |a_u - f_a/m| = 2 m/s^2 at f_a = 180 N
  return p;
}

// One seat in SI (double, float, Q23.40) or in the scene units of Q7.24, stepped with SI values.
template <typename T, typename Law>
struct SiSeat {
  Oscillator<T, Law> seat;
  bool configure(FrictionModel model) { return seat.configure(seat_params(model)).ok(); }
  void reset() { seat.reset(T(0), T(0), T(0)); }
  StepOutput<double> step(double a_u, double f_a) {
    const StepOutput<T> out = seat.step(from(a_u), from(f_a));
    return {to(out.x_r_m),
            to(out.v_r_m_per_s),
            to(out.a_x_m_per_s2),
            to(out.friction_n),
            to(out.stuck_time_s),
            to(out.stuck_fraction),
            out.stuck,
            out.events};
  }
  static T from(double value) { return ScalarTraits<T>::from_double(value); }
  static double to(T value) { return ScalarTraits<T>::to_double(value); }
};

template <typename Law>
struct ScaledSeat {
  ScaledOscillator<Fixed32, Law> seat;
  bool configure(FrictionModel model) { return seat.configure(seat_params(model)).ok(); }
  void reset() { seat.oscillator().reset(Fixed32(0), Fixed32(0), Fixed32(0)); }
  StepOutput<double> step(double a_u, double f_a) {
    const auto out = seat.step(seat.acceleration(a_u), seat.force(f_a));
    return {seat.to_si_displacement(out.x_r_m),
            seat.to_si_velocity(out.v_r_m_per_s),
            seat.to_si_acceleration(out.a_x_m_per_s2),
            seat.to_si_force(out.friction_n),
            seat.to_si_time(out.stuck_time_s),
            out.stuck_fraction.to_double(),
            out.stuck,
            out.events};
  }
};

struct Resolution {
  double relative;  // of a force or an acceleration against its own size
  double position_m;
};

// Below break-away: the force is held by friction at every step, nothing moves, a_x = a_u = 0.
template <typename Seat>
void check_held(Resolution tolerance) {
  for (double force : {0.9 * kStaticN, -0.999 * kStaticN}) {
    Seat s;
    CHECK(s.configure(FrictionModel::stick_slip));
    s.reset();
    for (int j = 0; j < 3000; ++j) {
      const StepOutput<double> out = s.step(0.0, force);
      CHECK(out.stuck);
      CHECK_EQUAL(0.0, out.x_r_m);
      CHECK_EQUAL(0.0, out.v_r_m_per_s);
      CHECK_EQUAL(0.0, out.a_x_m_per_s2);  // moves with the floor, exactly
      DOUBLES_EQUAL(force, out.friction_n, tolerance.relative * kStaticN);
    }
  }
}

// Above break-away: slips from t = 0, first rest at pi/w_d at x_e (1 + e^{-sigma pi/w_d}), where
// |F_L| = |F - k x| <= F_fs holds it for good.
template <typename Seat>
void check_breaks_away(Resolution tolerance, double force_n) {
  const double m = test::kMassKg, k = test::kStiffnessNPerM, b = test::kDampingNsPerM;
  const double d = force_n > 0 ? 1.0 : -1.0;
  const double x_e = (force_n - kKineticN * d) / k;
  const double sigma = b / (2 * m), w_d = std::sqrt(k / m - sigma * sigma);
  const double x_stop = x_e * (1 + std::exp(-sigma * kPi / w_d));
  CHECK(std::fabs(force_n - k * x_stop) <= kStaticN);  // the case sticks at its first rest
  Seat s;
  CHECK(s.configure(FrictionModel::stick_slip));
  s.reset();
  double slipping_s = 0.0;
  StepOutput<double> out{};
  for (int j = 0; j < 1000; ++j) {
    out = s.step(0.0, force_n);
    slipping_s += kDtS - out.stuck_time_s;
  }
  CHECK(out.stuck);
  DOUBLES_EQUAL(x_stop, out.x_r_m, tolerance.position_m);
  DOUBLES_EQUAL(kPi / w_d, slipping_s, 1e3 * tolerance.position_m);
  // Held: a_x = a_u = 0, friction F_L = F - k x_r.
  CHECK_EQUAL(0.0, out.a_x_m_per_s2);
  DOUBLES_EQUAL(force_n - k * out.x_r_m, out.friction_n, tolerance.relative * std::fabs(force_n));
}

// Without friction: the static deflection F/k, a_x -> 0 (after 60 decay times e^{-sigma t}).
template <typename Seat>
void check_static_deflection(Resolution tolerance) {
  const double force = 120.0;
  Seat s;
  CHECK(s.configure(FrictionModel::linear));
  s.reset();
  StepOutput<double> out{};
  for (int j = 0; j < 25000; ++j) out = s.step(0.0, force);
  DOUBLES_EQUAL(force / test::kStiffnessNPerM, out.x_r_m, tolerance.position_m);
  DOUBLES_EQUAL(0.0, out.a_x_m_per_s2, tolerance.relative * force / test::kMassKg);
}

// At an equilibrium of the discretised seat each step's rounding is amplified by 1/k', with
// k' = k dt^2/m = 1.3e-4 the stiffness in steps (the map's xx is 1 - O(k')). Double and Q23.40: far
// below the tolerances. Float: 2^-24 of x over k' bounds x to 1e-5 m; it lands within 2e-8. Q7.24
// (scene units, 24 fraction bits): k' itself is held to 2^-24/k' = 4.6e-4 of its value, which
// moves every equilibrium by up to that fraction: 6e-6 m at x = 0.014 m (3e-6 seen).
constexpr Resolution kDouble{1e-13, 1e-12};
constexpr Resolution kFloat{1e-5, 1e-6};
constexpr Resolution kFixed{1e-8, 1e-9};
constexpr Resolution kFixed32{1e-3, 8e-6};

}  // namespace

TEST_GROUP(ActuatorForce){};

TEST(ActuatorForce, BelowBreakAwayTheFrictionHoldsTheForceAndNothingMoves) {
  check_held<SiSeat<double, CoulombStickSlip>>(kDouble);
  check_held<SiSeat<float, CoulombStickSlip>>(kFloat);
  check_held<SiSeat<Fixed, CoulombStickSlip>>(kFixed);
  check_held<ScaledSeat<CoulombStickSlip>>(kFixed32);
}

TEST(ActuatorForce, AboveBreakAwayTheSeatStopsAtTheFirstTurningPointOfTheFreeDecay) {
  for (double force : {150.0, -180.0}) {
    check_breaks_away<SiSeat<double, CoulombStickSlip>>(kDouble, force);
    check_breaks_away<SiSeat<float, CoulombStickSlip>>(kFloat, force);
    check_breaks_away<SiSeat<Fixed, CoulombStickSlip>>(kFixed, force);
    check_breaks_away<ScaledSeat<CoulombStickSlip>>(kFixed32, force);
  }
}

TEST(ActuatorForce, WithoutFrictionTheSeatSettlesAtTheStaticDeflection) {
  check_static_deflection<SiSeat<double, NoFriction>>(kDouble);
  check_static_deflection<SiSeat<float, NoFriction>>(kFloat);
  check_static_deflection<SiSeat<Fixed, NoFriction>>(kFixed);
  check_static_deflection<ScaledSeat<NoFriction>>(kFixed32);
}

// A zero force is no force: step(a_u, 0) gives the outputs of step(a_u) for every law (the force
// shifts the input by -0/m = 0 and a_x by 0).
template <typename Law>
void check_zero_force(FrictionModel model) {
  const std::vector<double> a_u = test::make_lorry_signal(7, 1.5).sample(kDtS, 6000);
  Oscillator<double, Law> plain, actuated;
  CHECK(plain.configure(seat_params(model)).ok());
  CHECK(actuated.configure(seat_params(model)).ok());
  plain.reset(0.0, 0.0, a_u[0]);
  actuated.reset(0.0, 0.0, a_u[0], 0.0);
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<double> p = plain.step(a_u[n]);
    const StepOutput<double> q = actuated.step(a_u[n], 0.0);
    CHECK(p.x_r_m == q.x_r_m && p.v_r_m_per_s == q.v_r_m_per_s);
    CHECK(p.a_x_m_per_s2 == q.a_x_m_per_s2 && p.friction_n == q.friction_n);
    CHECK(p.stuck == q.stuck && p.stuck_time_s == q.stuck_time_s && p.events == q.events);
  }
}

TEST(ActuatorForce, AZeroForceGivesThePlainStepForEveryLaw) {
  check_zero_force<NoFriction>(FrictionModel::linear);
  check_zero_force<SignumFriction>(FrictionModel::signum);
  check_zero_force<SmoothFriction<SmoothingLaw::tanh>>(FrictionModel::smooth);
  check_zero_force<CoulombStickSlip>(FrictionModel::stick_slip);
  check_zero_force<StribeckStickSlip>(FrictionModel::stribeck);
}

// A non-finite force is replaced by none (passive) and counted.
TEST(ActuatorForce, ANonFiniteForceActsAsNoneAndIsCounted) {
  Oscillator<double, CoulombStickSlip> plain, actuated;
  CHECK(plain.configure(seat_params(FrictionModel::stick_slip)).ok());
  CHECK(actuated.configure(seat_params(FrictionModel::stick_slip)).ok());
  plain.reset(0.0, 0.0, 0.0);
  actuated.reset(0.0, 0.0, 0.0);
  const StepOutput<double> p = plain.step(3.0);
  const StepOutput<double> q = actuated.step(3.0, std::nan(""));
  CHECK(p.x_r_m == q.x_r_m && p.a_x_m_per_s2 == q.a_x_m_per_s2);
  LONGS_EQUAL(1, static_cast<long>(actuated.rejected_inputs()));
}
