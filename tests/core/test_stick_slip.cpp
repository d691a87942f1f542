// Stick-slip specifics: the stuck state, the stuck time inside a step, break-away instants,
// several events per step, and float against double.
#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <type_traits>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

constexpr double kKineticN = 35.0;
constexpr double kStaticN = 45.0;
constexpr double kLorryRms = 0.35;

const Integrator kAllIntegrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                      Integrator::exact};

OscillatorParams sticking_params(FrictionModel model, Integrator integrator, double dt_s) {
  OscillatorParams p = test::reference_params(model, integrator, dt_s);
  p.kinetic_friction_n = kKineticN;
  p.static_friction_n = kStaticN;
  p.stribeck_velocity_m_per_s = 0.01;
  return p;
}

template <typename T>
T ulp_of(T value) {
  return std::numeric_limits<T>::epsilon() * std::fabs(value);
}

struct StuckAudit {
  long stuck_steps = 0, slipping_steps = 0, event_steps = 0;
  bool a_x_is_a_u = true, v_is_zero = true, holds_limit_force = true, within_static = true;
  bool frozen = true;               // x unchanged across stuck steps without events
  bool stuck_time_in_range = true;  // 0 <= stuck_time <= dt, fraction in [0, 1], consistent
  bool whole_steps_exact = true;    // stuck throughout: fraction exactly 1; slipping: 0
  bool slip_friction_is_law = true;
};

// Lorry-like run auditing every step against the stick-slip definitions.
template <typename T, typename Law>
StuckAudit audit_run(Integrator integrator, double dt, long steps) {
  const auto signal = test::make_lorry_signal(42, kLorryRms);
  Oscillator<T, Law> seat;
  const OscillatorParams params = sticking_params(Law::model, integrator, dt);
  const auto config = seat.configure(params);
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(T(0), T(0), static_cast<T>(signal.at(0.0)));
  const T m = static_cast<T>(test::kMassKg), k = static_cast<T>(test::kStiffnessNPerM);
  const T step_s = seat.dt_s();
  StuckAudit audit;
  bool was_stuck = seat.current().stuck;
  T previous_x = seat.current().x_r_m;
  for (long n = 1; n <= steps; ++n) {
    const T a_u = static_cast<T>(signal.at(static_cast<double>(n) * dt));
    const auto out = seat.step(a_u);
    if (out.events > 0) ++audit.event_steps;
    if (!(out.stuck_time_s >= T(0) && out.stuck_time_s <= step_s && out.stuck_fraction >= T(0) &&
          out.stuck_fraction <= T(1) &&
          std::fabs(out.stuck_time_s - out.stuck_fraction * step_s) <= ulp_of(step_s)))
      audit.stuck_time_in_range = false;
    if (out.stuck) {
      ++audit.stuck_steps;
      if (!test::same_bits(out.a_x_m_per_s2, a_u)) audit.a_x_is_a_u = false;
      if (!(out.v_r_m_per_s == T(0))) audit.v_is_zero = false;
      const T limit = -(m * a_u + k * out.x_r_m);
      if (std::fabs(out.friction_n - limit) > T(4) * (ulp_of(m * a_u) + ulp_of(k * out.x_r_m)))
        audit.holds_limit_force = false;
      if (std::fabs(out.friction_n) > static_cast<T>(kStaticN)) audit.within_static = false;
      if (was_stuck && out.events == 0) {
        if (!(out.x_r_m == previous_x)) audit.frozen = false;
        if (!(out.stuck_fraction == T(1))) audit.whole_steps_exact = false;
      }
    } else {
      ++audit.slipping_steps;
      if (!was_stuck && out.events == 0 && !(out.stuck_fraction == T(0)))
        audit.whole_steps_exact = false;
      // Slipping friction is the law at the output velocity, in the direction of motion.
      if (out.v_r_m_per_s != T(0)) {
        const T d = out.v_r_m_per_s > T(0) ? T(1) : T(-1);
        T expected = static_cast<T>(kKineticN) * d;
        if (Law::model == FrictionModel::stribeck) {
          const double r = static_cast<double>(out.v_r_m_per_s) / 0.01;
          const double excess = r * r > 80.0 ? 0.0 : (kStaticN - kKineticN) * std::exp(-r * r);
          expected = static_cast<T>((kKineticN + excess) * static_cast<double>(d));
        }
        if (std::fabs(out.friction_n - expected) > T(8) * ulp_of(static_cast<T>(kStaticN)))
          audit.slip_friction_is_law = false;
      }
    }
    was_stuck = out.stuck;
    previous_x = out.x_r_m;
  }
  CHECK_EQUAL(0u, seat.event_budget_exhausted());
  // The float Stribeck law squares a ~1e-20 m/s break-away velocity, which can underflow; that is
  // judged by FloatStribeckBreakAwayRaisesNoUnderflow. Cleared here so that this test judges only
  // the stuck-state definitions it states.
  if (sizeof(T) == sizeof(float) && Law::model == FrictionModel::stribeck)
    std::feclearexcept(FE_UNDERFLOW);
  return audit;
}

template <typename T, typename Law>
void check_audit(Integrator integrator, double dt) {
  const long steps = std::lround(30.0 / dt);
  const StuckAudit a = audit_run<T, Law>(integrator, dt, steps);
  const SimpleString what =
      StringFromFormat("%s %s %s dt = %g", sizeof(T) == 4 ? "float" : "double",
                       model_name(Law::model), integrator_name(integrator), dt);
  // Both states well represented (each over 10 % of the steps) and many transitions.
  CHECK_TEXT(a.stuck_steps > steps / 10 && a.slipping_steps > steps / 10 && a.event_steps > 50,
             StringFromFormat("%s: %ld stuck, %ld slipping, %ld with events", what.asCharString(),
                              a.stuck_steps, a.slipping_steps, a.event_steps)
                 .asCharString());
  CHECK_TEXT(a.a_x_is_a_u, (what + ": stuck a_x != a_u").asCharString());
  CHECK_TEXT(a.v_is_zero, (what + ": stuck v_r != 0").asCharString());
  CHECK_TEXT(a.holds_limit_force, (what + ": stuck friction != -(m a_u + k x_r)").asCharString());
  CHECK_TEXT(a.within_static, (what + ": holding force beyond F_fs").asCharString());
  CHECK_TEXT(a.frozen, (what + ": stuck seat moved").asCharString());
  CHECK_TEXT(a.stuck_time_in_range, (what + ": stuck time outside [0, dt]").asCharString());
  CHECK_TEXT(a.whole_steps_exact, (what + ": whole-step stuck fraction not 0/1").asCharString());
  CHECK_TEXT(a.slip_friction_is_law, (what + ": slipping friction not the law").asCharString());
}

// Stuck at rest at x_s with F_L = -(m a_u + k x_s), the input linear from a0 to a1 over the step.
// Returns the stuck fraction of the step: 1 if |F_L| stays within F_fs, else the root of
// |F_L(phi)| = F_fs (F_L is linear in phi).
double break_away_fraction(double x_s, double a0, double a1) {
  const double f0 = -(test::kMassKg * a0 + test::kStiffnessNPerM * x_s);
  const double f1 = -(test::kMassKg * a1 + test::kStiffnessNPerM * x_s);
  if (std::fabs(f1) <= kStaticN) return 1.0;
  const double d = f1 > 0.0 ? 1.0 : -1.0;
  return (d * kStaticN - f0) / (f1 - f0);
}

struct LorryStats {
  double transmissibility, stick_probability;
};

template <typename T>
LorryStats lorry_statistics(double seconds, double dt) {
  const auto signal = test::make_lorry_signal(2024, kLorryRms);
  Oscillator<T, CoulombStickSlip> seat;
  CHECK(seat.configure(sticking_params(FrictionModel::stick_slip, Integrator::exact, dt)).ok());
  const T a0 = static_cast<T>(signal.at(0.0));
  seat.reset(T(0), T(0), a0);
  RunningStatistics<T> stats;
  stats.add_sample(a0, seat.current().a_x_m_per_s2);
  const long steps = std::lround(seconds / dt);
  for (long n = 1; n <= steps; ++n) {
    const T a = static_cast<T>(signal.at(static_cast<double>(n) * dt));
    const auto out = seat.step(a);
    stats.add_sample(a, out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
  }
  CHECK_EQUAL(0u, seat.event_budget_exhausted());
  return {stats.transmissibility(), stats.stick_probability()};
}

// Laws with the safety limit as their budget: a step that held more events than the derived
// bound would show them.
struct StribeckAtTheSafetyLimit : StribeckStickSlip {
  static constexpr int kEventBudget = kMaxEventsPerStep;
};

struct CoulombAtTheSafetyLimit : CoulombStickSlip {
  static constexpr int kEventBudget = kMaxEventsPerStep;
};

struct StribeckTally {
  int most_events = 0;                  // counted with the safety limit as the budget
  long steps_at_the_bound = 0;          // steps with kMaxEventsOfTheExactSolutionPerStep events
  long steps_apart = 0;                 // the seat with the default budget stepped otherwise
  double worst_x = 0.0, worst_v = 0.0;  // 3-event steps: apart, in epsilons of the step's scale
};

// One step of the counting seat and, from its state, of the seat with the default budget (both
// restored to it, so that each step is compared on its own): bit for bit below the bound; at it,
// the same events and mode, where the default seat slips the rest of the step unsearched.
template <typename T>
void step_stribeck_alike(const OscillatorParams& p,
                         Oscillator<T, StribeckAtTheSafetyLimit>& counting,
                         Oscillator<T, StribeckStickSlip>& seat, T a_u, T f_a,
                         StribeckTally& tally) {
  const auto s = counting.state();
  counting.restore(s);
  seat.restore(
      {s.x_r_m, s.v_r_m_per_s, s.a_u_previous, s.direction, s.held_force_n, s.reported_force_n});
  const StepOutput<T> expected = counting.step(a_u, f_a);
  const StepOutput<T> got = seat.step(a_u, f_a);
  tally.most_events = std::max(tally.most_events, static_cast<int>(expected.events));
  if (expected.events < kMaxEventsOfTheExactSolutionPerStep) {
    if (!test::same_bits(expected, got)) ++tally.steps_apart;
    return;
  }
  ++tally.steps_at_the_bound;
  if (got.events != expected.events || got.stuck != expected.stuck) ++tally.steps_apart;
  // The last slip, searched or not, is the same piece of the exact solution from the same event:
  // the two differ by rounding alone, in units of T's epsilon times the step's scales (its
  // largest relative acceleration over the step for v_r, and that times dt for x_r).
  const double x = static_cast<double>(s.x_r_m), a = static_cast<double>(a_u);
  const double accel = std::fabs(a) + (p.stiffness_n_per_m * std::fabs(x) + p.static_friction_n +
                                       std::fabs(static_cast<double>(f_a))) /
                                          p.mass_kg;
  const double v_scale = std::fabs(static_cast<double>(s.v_r_m_per_s)) + accel * p.dt_s;
  const double x_scale = std::fabs(x) + v_scale * p.dt_s;
  const double eps = static_cast<double>(std::numeric_limits<T>::epsilon());
  tally.worst_x = std::max(tally.worst_x, std::fabs(static_cast<double>(got.x_r_m) -
                                                    static_cast<double>(expected.x_r_m)) /
                                              (eps * x_scale));
  tally.worst_v = std::max(tally.worst_v, std::fabs(static_cast<double>(got.v_r_m_per_s) -
                                                    static_cast<double>(expected.v_r_m_per_s)) /
                                              (eps * v_scale));
}

}  // namespace

TEST_GROUP(StickSlip){};

// Every stuck step of a long lorry-like run, for every integrator, both sticking laws, float and
// double: a_x == a_u exactly, v_r == 0, friction = -(m a_u + k x_r) within F_fs, x_r frozen;
// every step: 0 <= stuck_time <= dt, whole stuck steps count 1, whole slipping steps 0; slipping
// friction is F_fk sgn(v) (Coulomb) or the Stribeck curve.
TEST(StickSlip, StuckSeatMovesWithTheFloorAndHoldsTheLimitForce) {
  for (Integrator integrator : kAllIntegrators) {
    for (double dt : {1e-3, 1e-2}) {
      check_audit<double, CoulombStickSlip>(integrator, dt);
      check_audit<double, StribeckStickSlip>(integrator, dt);
      check_audit<float, CoulombStickSlip>(integrator, dt);
    }
  }
}

// Float Stribeck separately: it also exercises the break-away of a velocity-dependent law in float.
TEST(StickSlip, FloatStribeckStuckStateIsExact) {
  for (Integrator integrator : kAllIntegrators)
    check_audit<float, StribeckStickSlip>(integrator, 1e-3);
}

// Stuck at rest under a ramp a_u = r t (represented exactly by the hold): F_L = -m r t reaches
// F_fs at t* = F_fs/(m r). Every step before is wholly stuck, the step containing t* is stuck for
// exactly t* - t[j-1], and p over the run is t*/T.
TEST(StickSlip, BreakAwayInstantOfARampIsExact) {
  double worst = 0.0;
  for (Integrator integrator : kAllIntegrators) {
    for (double dt : {1e-4, 1e-3, 7e-3, 0.04}) {  // 0.04 s: inside Euler's limit b/k
      for (double rate : {0.37, -1.3, 9.1}) {     // m/s^3
        Oscillator<double, CoulombStickSlip> seat;
        CHECK(seat.configure(sticking_params(FrictionModel::stick_slip, integrator, dt)).ok());
        seat.reset(0.0, 0.0, 0.0);
        const double t_break = kStaticN / (test::kMassKg * std::fabs(rate));
        const long j_break = static_cast<long>(std::ceil(t_break / dt));
        CHECK(std::fabs(t_break / dt - std::round(t_break / dt)) > 1e-6);  // not on a sample
        RunningStatistics<double> stats;
        for (long j = 1; j <= j_break; ++j) {
          const auto out = seat.step(rate * static_cast<double>(j) * dt);
          stats.add_step(out.stuck_fraction);
          if (j < j_break) {
            CHECK(out.stuck);
            CHECK_EQUAL(dt, out.stuck_time_s);
            LONGS_EQUAL(0, out.events);
          } else {
            CHECK_FALSE(out.stuck);
            CHECK(out.events >= 1);
            const double expected = t_break - static_cast<double>(j_break - 1) * dt;
            const double error = std::fabs(out.stuck_time_s - expected);
            CHECK_TEXT(
                error < 1e-12,
                StringFromFormat("%s dt = %g r = %g: stuck time %.17g vs %.17g",
                                 integrator_name(integrator), dt, rate, out.stuck_time_s, expected)
                    .asCharString());
            worst = std::max(worst, error);
          }
        }
        const double p_expected = t_break / (static_cast<double>(j_break) * dt);
        DOUBLES_EQUAL(p_expected, stats.stick_probability(), 1e-12);
      }
    }
  }
  test::note_margin("ramp break-away stuck time error, s", worst, 1e-12);
}

// Stuck off-centre (x_s != 0, spring preloaded) with the input jumping within one step: the
// stuck fraction is the root of the linear |F_L(phi)| = F_fs, for both break-away directions.
TEST(StickSlip, BreakAwayFractionOfAPreloadedSeatIsTheRootOfTheLinearLimitForce) {
  struct Case {
    double x_s, a0, a1;
  };
  const Case cases[] = {
      {0.003, 0.0, 0.5},    // F_L: -34.5 N -> -78.7 N, breaks negative
      {0.003, 0.0, -0.9},   // -34.5 -> +45.06: just, positive
      {-0.002, 0.2, -2.0},  // +5.3 -> +199.8
      {0.0, 0.3, 0.3},      // stays stuck: fraction 1
      {0.0039, -0.1, 0.45},
  };
  double worst = 0.0;
  for (double dt : {1e-3, 0.05}) {
    for (const Case& c : cases) {
      const double limit0 = -(test::kMassKg * c.a0 + test::kStiffnessNPerM * c.x_s);
      CHECK(std::fabs(limit0) <= kStaticN);  // it does start stuck
      Oscillator<double, CoulombStickSlip> seat;
      CHECK(seat.configure(sticking_params(FrictionModel::stick_slip, Integrator::exact, dt)).ok());
      seat.reset(c.x_s, 0.0, c.a0);
      CHECK(seat.current().stuck);
      const auto out = seat.step(c.a1);
      const double expected = break_away_fraction(c.x_s, c.a0, c.a1);
      const double error = std::fabs(out.stuck_fraction - expected);
      CHECK_TEXT(error < 1e-12,
                 StringFromFormat("x_s = %g a0 = %g a1 = %g dt = %g: fraction %.17g vs %.17g",
                                  c.x_s, c.a0, c.a1, dt, out.stuck_fraction, expected)
                     .asCharString());
      DOUBLES_EQUAL(expected * dt, out.stuck_time_s, 1e-12 * dt);
      worst = std::max(worst, error);
    }
  }
  test::note_margin("preloaded break-away fraction error", worst, 1e-12);
}

// dt = 0.05 s with a 9 Hz + 20.7 Hz input: up to three events (break-away, stick, break-away...)
// inside one step, well within the event budget; and the states at every sample agree with a run
// 1000 times finer on the identical piecewise-linear input (event-driven exactness).
TEST(StickSlip, SeveralEventsInOneLargeStepMatchAFineRun) {
  const double dt = 0.05;
  const std::size_t samples = 2001;  // 100 s
  std::vector<double> input(samples);
  for (std::size_t n = 0; n < samples; ++n) {
    const double t = static_cast<double>(n) * dt;
    input[n] = 2.0 * std::sin(2.0 * kPi * 9.0 * t) + 1.0 * std::sin(2.0 * kPi * 20.7 * t + 1.0);
  }
  OscillatorParams p = sticking_params(FrictionModel::stick_slip, Integrator::exact, dt);
  p.kinetic_friction_n = 40.0;
  p.static_friction_n = 50.0;
  Oscillator<double, CoulombStickSlip> coarse, fine;
  CHECK(coarse.configure(p).ok());
  p.dt_s = dt / 1000.0;
  CHECK(fine.configure(p).ok());
  coarse.reset(0.0, 0.0, input[0]);
  fine.reset(0.0, 0.0, input[0]);
  int most_events = 0, multi_event_steps = 0;
  double worst = 0.0;
  for (std::size_t n = 1; n < samples; ++n) {
    const auto out = coarse.step(input[n]);
    most_events = std::max(most_events, static_cast<int>(out.events));
    if (out.events >= 2) ++multi_event_steps;
    StepOutput<double> fine_out{};
    for (std::size_t r = 1; r <= 1000; ++r)
      fine_out = fine.step(test::refine_linear(input, (n - 1) * 1000 + r, 1000));
    worst = std::max(worst, std::fabs(out.x_r_m - fine_out.x_r_m));
    CHECK(out.stuck == fine_out.stuck);
  }
  CHECK_TEXT(most_events >= 3,
             StringFromFormat("most events in a step: %d", most_events).asCharString());
  CHECK(multi_event_steps > 100);
  CHECK_EQUAL(0u, coarse.event_budget_exhausted());
  CHECK_EQUAL(0u, fine.event_budget_exhausted());
  CHECK_TEXT(worst < 1e-9,
             StringFromFormat("max |x(0.05) - x(5e-5)| = %.3e m", worst).asCharString());
  test::note_margin("multi-event step vs fine run, m", worst, 1e-9);
  test::note_margin("most events in one step", most_events, kMaxEventsPerStep);
}

// The bound step_common.hpp derives, the event budget of every scalar for a constant slip force:
// no step configure() accepts (omega0 dt <= pi/2) holds more than
// kMaxEventsOfTheExactSolutionPerStep events of the exact solution. They are counted on a run kFine
// times finer on the identical piecewise-linear input, whose budget cannot cut a coarse step's
// events short (a sub-step holds a fraction of them). The coarse run in double locates exactly the
// events the fine run counts, step by step, and no coarse run loses one (event_budget_exhausted()
// stays 0): double, float and Q23.40, and the held signum law in double and float. Stribeck, whose
// force the exact integrator holds over each piece of motion (the bound's derivation covers it),
// is counted by seats whose declared budget is the safety limit, kMaxEventsPerStep, so that the
// budget cannot hide a step with more: most 3, reached, in double and float, and the seats with
// the default budget of 3 step bit for bit as they do. Hostile inputs: a_u jumping every sample
// across a range that carries F_L past +-F_fs and back, and an actuator force that jumps at samples
// (so that break-aways at a step's start go against F_L's motion), at steps up to the acceptance
// limit.
TEST(StickSlip, NoStepOfTheExactSolutionHoldsMoreEventsThanTheDerivedBound) {
  constexpr int kFine = 32;
  int most_events = 0;
  long steps_at_the_bound = 0, steps = 0, steps_counted_alike = 0;
  StribeckTally stribeck_tally, stribeck_float_tally;
  for (const double damping : {0.0, 504.0}) {
    for (const double static_over_kinetic : {1.0, 1.3}) {
      OscillatorParams p = sticking_params(FrictionModel::stick_slip, Integrator::exact, 1e-3);
      const double omega0 = std::sqrt(p.stiffness_n_per_m / p.mass_kg);
      for (const double dt : {1e-3, 1e-2, 5e-2, 0.1, 0.5 * kPi / omega0}) {
        p.dt_s = dt;
        p.damping_ns_per_m = damping;
        p.static_friction_n = static_over_kinetic * p.kinetic_friction_n;
        Oscillator<double, CoulombStickSlip> seat, fine;
        Oscillator<float, CoulombStickSlip> seat_float;
        Oscillator<Fixed, CoulombStickSlip> seat_fixed;
        Oscillator<double, SignumFriction> signum;  // held at rest to the step's end
        Oscillator<float, SignumFriction> signum_float;
        Oscillator<double, StribeckStickSlip> stribeck;
        Oscillator<float, StribeckStickSlip> stribeck_float;
        Oscillator<double, StribeckAtTheSafetyLimit> stribeck_counting;
        Oscillator<float, StribeckAtTheSafetyLimit> stribeck_float_counting;
        CHECK(seat.configure(p).ok());
        CHECK(seat_float.configure(p).ok());
        CHECK(seat_fixed.configure(p).ok());
        OscillatorParams signum_params = p;
        signum_params.model = FrictionModel::signum;
        signum_params.static_friction_n = p.kinetic_friction_n;
        CHECK(signum.configure(signum_params).ok());
        CHECK(signum_float.configure(signum_params).ok());
        OscillatorParams stribeck_params = p;
        stribeck_params.model = FrictionModel::stribeck;
        stribeck_params.static_friction_n = 1.3 * p.kinetic_friction_n;
        CHECK(stribeck.configure(stribeck_params).ok());
        CHECK(stribeck_float.configure(stribeck_params).ok());
        CHECK(stribeck_counting.configure(stribeck_params).ok());
        CHECK(stribeck_float_counting.configure(stribeck_params).ok());
        OscillatorParams fine_params = p;
        fine_params.dt_s = dt / kFine;
        CHECK(fine.configure(fine_params).ok());
        test::SplitMix64 random(static_cast<std::uint64_t>(1000.0 * dt + damping) + 7u);
        // a_u swings F_L by up to 3 F_fs from sample to sample, about the holding point.
        const double swing = 3.0 * p.static_friction_n / p.mass_kg;
        double a_before = 0.0;
        for (int n = 0; n < 10000; ++n) {
          const double centre = -p.stiffness_n_per_m * seat.x_r() / p.mass_kg;
          const double a_u = centre + swing * random.uniform(-1.0, 1.0);
          const double f_a =
              (n % 5 == 0) ? 0.5 * p.static_friction_n * random.uniform(-1.0, 1.0) : 0.0;
          const auto out = seat.step(a_u, f_a);
          seat_float.step(static_cast<float>(a_u), static_cast<float>(f_a));
          seat_fixed.step(Fixed(a_u), Fixed(f_a));
          signum.step(a_u, f_a);
          signum_float.step(static_cast<float>(a_u), static_cast<float>(f_a));
          step_stribeck_alike(stribeck_params, stribeck_counting, stribeck, a_u, f_a,
                              stribeck_tally);
          step_stribeck_alike(stribeck_params, stribeck_float_counting, stribeck_float,
                              static_cast<float>(a_u), static_cast<float>(f_a),
                              stribeck_float_tally);
          int events = 0;
          for (int r = 1; r <= kFine; ++r) {
            const double a_r = a_before + (a_u - a_before) * r / kFine;
            events += fine.step(r == kFine ? a_u : a_r, f_a).events;
          }
          a_before = a_u;
          most_events = std::max(most_events, events);
          if (events == kMaxEventsOfTheExactSolutionPerStep) ++steps_at_the_bound;
          ++steps;
          if (events == out.events) ++steps_counted_alike;
        }
        CHECK_EQUAL(0u, seat.event_budget_exhausted());
        CHECK_EQUAL(0u, seat_float.event_budget_exhausted());
        CHECK_EQUAL(0u, seat_fixed.event_budget_exhausted());
        CHECK_EQUAL(0u, seat_fixed.saturated_steps());
        CHECK_EQUAL(0u, signum.event_budget_exhausted());
        CHECK_EQUAL(0u, signum_float.event_budget_exhausted());
        CHECK_EQUAL(0u, fine.event_budget_exhausted());
        CHECK_EQUAL(0u, stribeck.event_budget_exhausted());
        CHECK_EQUAL(0u, stribeck_float.event_budget_exhausted());
        CHECK_EQUAL(0u, stribeck_counting.event_budget_exhausted());
        CHECK_EQUAL(0u, stribeck_float_counting.event_budget_exhausted());
      }
    }
  }
  test::note_margin("most events in a step", most_events, kMaxEventsOfTheExactSolutionPerStep);
  test::note_margin("steps at the bound", static_cast<double>(steps_at_the_bound), 0.0);
  test::note_margin("steps whose events the fine run counts otherwise",
                    static_cast<double>(steps - steps_counted_alike), 0.0);
  CHECK_TEXT(most_events <= kMaxEventsOfTheExactSolutionPerStep,
             StringFromFormat("a step held %d events", most_events).asCharString());
  CHECK(steps_at_the_bound > 0);  // the inputs do reach the bound
  LONGS_EQUAL(steps, steps_counted_alike);
  static_assert(Oscillator<double, StribeckStickSlip>::kEventBudget ==
                kMaxEventsOfTheExactSolutionPerStep);
  // Each path's state at the step's end is a few rounded terms of at most the step's scales:
  // two paths differ by a few units of epsilon of those scales at most.
  for (const StribeckTally* t : {&stribeck_tally, &stribeck_float_tally}) {
    LONGS_EQUAL(kMaxEventsOfTheExactSolutionPerStep, t->most_events);
    CHECK(t->steps_at_the_bound > 0);
    LONGS_EQUAL(0, t->steps_apart);
    CHECK_TEXT(
        t->worst_x <= 4.0 && t->worst_v <= 4.0,
        StringFromFormat("3-event steps apart by %.3g (x_r), %.3g (v_r) epsilons of their scales",
                         t->worst_x, t->worst_v)
            .asCharString());
    test::note_margin("Stribeck 3-event steps, x_r apart in epsilons", t->worst_x, 4.0);
    test::note_margin("Stribeck 3-event steps, v_r apart in epsilons", t->worst_v, 4.0);
  }
}

// A slip that breaks away towards the way F_L moves does not return to rest in its step
// (step_common.hpp); at a break-away a_r ~ 0, and float's rounding once found a return there,
// stuck the seat and broke it away again: 4 events where the bound is 3. Three such steps, found
// on random seats and hostile floors (a slip entering the step comes to rest, sticks, and breaks
// away; F_fs = F_fk for Coulomb, F_fs > F_fk for one Stribeck seat), stepped in float with the
// safety limit as the budget from the state before them: float holds the events double holds,
// and its stuck time differs from double's by no more than F_L's float rounding moves the
// break-away (8 epsilons of F_L's terms over F_L's change across the step).
TEST(StickSlip, FloatBreakAwayTowardsTheLoadsMotionDoesNotReturnToRestByRounding) {
  struct Case {
    FrictionModel model;
    double mass_kg, stiffness_n_per_m, damping_ns_per_m, kinetic_n, static_n, stribeck_m_per_s,
        dt_s;
    float x_r_m, v_r_m_per_s, a_u_previous, a_u;
  };
  const Case cases[] = {
      {FrictionModel::stick_slip, 0x1.90bf0e4b93578p+5, 0x1.0cdaa1d677b4ep+12, 0x1.49bbeaa0305b7p+8,
       0x1.52db8e25636ep+6, 0x1.52db8e25636ep+6, 0x1.2f48d36da3fd7p-5, 0x1.0eab31a3b44fcp-3,
       -0x1.813f42p+1f, -0x1.6574p-6f, 0x1.056be8p+8f, 0x1.0013fcp+8f},
      {FrictionModel::stribeck, 0x1.90bf0e4b93578p+5, 0x1.0cdaa1d677b4ep+12, 0x1.49bbeaa0305b7p+8,
       0x1.52db8e25636ep+6, 0x1.52db8e25636ep+6, 0x1.2f48d36da3fd7p-5, 0x1.0eab31a3b44fcp-3,
       -0x1.813f42p+1f, -0x1.6574p-6f, 0x1.056be8p+8f, 0x1.0013fcp+8f},
      {FrictionModel::stribeck, 0x1.06956d1e8056ep+6, 0x1.8cb974226c861p+14, 0x1.ce4e8246866e9p+8,
       0x1.2adf1074394ccp+6, 0x1.65e697363fa9fp+6, 0x1.8876a5d7fa1cbp-6, 0x1.596bb75fe3c3fp-5,
       0x1.15721cp-2f, -0x1.5986p-6f, -0x1.a7ae3cp+6f, -0x1.a884e6p+6f},
  };
  for (const Case& c : cases) {
    OscillatorParams p;
    p.model = c.model;
    p.integrator = Integrator::exact;
    p.mass_kg = c.mass_kg;
    p.stiffness_n_per_m = c.stiffness_n_per_m;
    p.damping_ns_per_m = c.damping_ns_per_m;
    p.kinetic_friction_n = c.kinetic_n;
    p.static_friction_n = c.static_n;
    p.stribeck_velocity_m_per_s = c.stribeck_m_per_s;
    p.dt_s = c.dt_s;
    const auto step_from = [&](auto& seat) {
      using T = typename std::decay_t<decltype(seat)>::Scalar;
      CHECK(seat.configure(p).ok());
      auto state = seat.state();
      state.x_r_m = static_cast<T>(c.x_r_m);
      state.v_r_m_per_s = static_cast<T>(c.v_r_m_per_s);
      state.a_u_previous = static_cast<T>(c.a_u_previous);
      state.direction = T(-1);
      seat.restore(state);
      return seat.step(static_cast<T>(c.a_u), T(0));
    };
    StepOutput<float> got{};
    StepOutput<double> expected{};
    if (c.model == FrictionModel::stick_slip) {
      Oscillator<float, CoulombAtTheSafetyLimit> seat;
      Oscillator<double, CoulombAtTheSafetyLimit> reference;
      got = step_from(seat);
      expected = step_from(reference);
    } else {
      Oscillator<float, StribeckAtTheSafetyLimit> seat;
      Oscillator<double, StribeckAtTheSafetyLimit> reference;
      got = step_from(seat);
      expected = step_from(reference);
    }
    LONGS_EQUAL(2, expected.events);  // a return to rest that sticks, a break-away
    LONGS_EQUAL(expected.events, got.events);
    CHECK_EQUAL(expected.stuck, got.stuck);
    const double terms_n = c.mass_kg * std::fabs(static_cast<double>(c.a_u)) +
                           c.stiffness_n_per_m * std::fabs(static_cast<double>(c.x_r_m)) +
                           c.static_n;
    const double change_n =
        c.mass_kg * std::fabs(static_cast<double>(c.a_u) - static_cast<double>(c.a_u_previous));
    const double tolerance =
        8.0 * static_cast<double>(std::numeric_limits<float>::epsilon()) * terms_n / change_n;
    DOUBLES_EQUAL(expected.stuck_fraction, static_cast<double>(got.stuck_fraction), tolerance);
  }
}

// Float and double on 120 s of lorry-like input: T_ax within 1e-4 relative, p within 1e-4.
TEST(StickSlip, FloatAndDoubleAgreeOnTransmissibilityAndStickProbability) {
  const LorryStats d = lorry_statistics<double>(120.0, 1e-3);
  const LorryStats f = lorry_statistics<float>(120.0, 1e-3);
  const double t_rel = std::fabs(f.transmissibility / d.transmissibility - 1.0);
  const double p_abs = std::fabs(f.stick_probability - d.stick_probability);
  CHECK_TEXT(t_rel < 1e-4,
             StringFromFormat("T_ax float %.7f double %.7f", f.transmissibility, d.transmissibility)
                 .asCharString());
  CHECK_TEXT(p_abs < 1e-4,
             StringFromFormat("p float %.7f double %.7f", f.stick_probability, d.stick_probability)
                 .asCharString());
  CHECK(d.stick_probability > 0.2 && d.stick_probability < 0.95);
  test::note_margin("float vs double T_ax rel. diff", t_rel, 1e-4);
  test::note_margin("float vs double p abs. diff", p_abs, 1e-4);
}

// A float Stribeck seat breaking away starts with v_r ~ jerk h^2 (~1e-20 m/s for a short remainder
// of a tick); the law squares v_r, which must not underflow to a subnormal (the core promises no
// subnormals: IEEE754 underflow fails the test, and subnormals are slow or flushed on MCUs).
TEST(StickSlip, FloatStribeckBreakAwayRaisesNoUnderflow) {
  OscillatorParams p = sticking_params(FrictionModel::stribeck, Integrator::exact, 1e-3);
  p.kinetic_friction_n = 40.0;
  p.static_friction_n = 50.0;
  Oscillator<float, StribeckStickSlip> seat;
  CHECK(seat.configure(p).ok());
  int underflows = 0;
  float first = 0.0f;
  for (int i = 1; i <= 2000; ++i) {
    // Jumps just above break-away (m a1 = F_fs (1 + i/1000)), from rest.
    const float a1 = 50.0f / 88.4f * (1.0f + static_cast<float>(i) * 1e-3f);
    seat.reset(0.0f, 0.0f, 0.0f);
    std::feclearexcept(FE_ALL_EXCEPT);
    seat.step(a1);
    if (std::fetestexcept(FE_UNDERFLOW) != 0) {
      if (underflows++ == 0) first = a1;
    }
  }
  std::feclearexcept(FE_ALL_EXCEPT);
  CHECK_TEXT(underflows == 0, StringFromFormat("%d inputs underflow, first a1 = %.9g m/s^2",
                                               underflows, static_cast<double>(first))
                                  .asCharString());
}

// A float Stribeck seat whose excess F_fs - F_fk is small (here 1e-5 N) would form excess
// exp(-(v/v_S)^2) at speed as a subnormal (7e-41 N at v = 9 v_S): the term stays at the least
// normal the law forms it with (stribeck_min_exponential()), and the friction at speed is F_fk.
TEST(StickSlip, FloatStribeckWithASmallExcessRaisesNoUnderflowAtSpeed) {
  OscillatorParams p = sticking_params(FrictionModel::stribeck, Integrator::exact, 1e-3);
  p.kinetic_friction_n = 0.01;
  p.static_friction_n = 0.01 + 1e-5;
  p.stribeck_velocity_m_per_s = 0.01;
  Oscillator<float, StribeckStickSlip> seat;
  CHECK(seat.configure(p).ok());
  int underflows = 0, first = -1;
  long fast_steps = 0;
  for (int n = 0; n < 5000; ++n) {
    std::feclearexcept(FE_ALL_EXCEPT);
    const StepOutput<float> out = seat.step((n / 100) % 2 == 0 ? -20.0f : 20.0f);
    if (std::fetestexcept(FE_UNDERFLOW) != 0 && underflows++ == 0) first = n;
    if (!out.stuck && std::fabs(out.v_r_m_per_s) > 9.0f * 0.01f) {
      ++fast_steps;
      CHECK_EQUAL(0.01f, std::fabs(out.friction_n));
    }
  }
  std::feclearexcept(FE_ALL_EXCEPT);
  CHECK_TEXT(
      underflows == 0,
      StringFromFormat("%d steps underflow, the first step %d", underflows, first).asCharString());
  CHECK(fast_steps > 1000);
}

namespace {

// A seat held at its break-away threshold by a floor chosen from its own state: F_L on +-F_fs,
// alternating every 7 samples, with offsets down to 1e-8 m/s^2, between seconds of jumps and
// swings. Random seats (test::random_sticking_seat()).
template <typename T, typename Law>
void hold_random_seat_at_the_threshold(const OscillatorParams& p, std::uint64_t seed,
                                       int& most_events, std::uint64_t& exhausted,
                                       long& stuck_steps) {
  Oscillator<T, Law> seat;
  CHECK_TRUE(seat.configure(p).ok());
  test::SplitMix64 random(seed);
  const double m = p.mass_kg, f_fs = p.static_friction_n;
  for (long n = 0; n < 6000; ++n) {
    const double holding = -p.stiffness_n_per_m * static_cast<double>(seat.x_r()) / m;
    const test::HostileFloor kinds[3] = {test::HostileFloor::noise, test::HostileFloor::threshold,
                                         test::HostileFloor::swing};
    const double a_u = test::hostile_floor(kinds[(n / 300) % 3], n, holding, f_fs / m, random);
    const StepOutput<T> out = seat.step(static_cast<T>(a_u));
    most_events = std::max(most_events, static_cast<int>(out.events));
    if (out.stuck) ++stuck_steps;
  }
  exhausted += seat.event_budget_exhausted();
}

}  // namespace

// At the threshold with F_fk = F_fs the exact motion is a slip too slow for the scalar to see.
// Float decided it from F_L's rounding, as a reversal, and as a stick that broke away at once,
// each an event a tick apart or less, until the budget ran out (Coulomb: 3, the exact solution's
// bound; Stribeck: 32), in 72 of these 960,000 steps. Now a seat at rest counts |F_L| within its
// rounding of F_fs as held, breaks away where F_L reaches F_fs on the far side of the band, and a
// slip that stays at rest to rounding holds no event (holding_limit_n(), rest_rounding_velocity()).
// No step may exhaust the budget, and none may hold more events than the exact solution can.
TEST(StickSlip, RandomSeatsHeldAtTheBreakAwayThresholdNeverExhaustTheEventBudget) {
  test::SplitMix64 random(21);
  int most_events = 0;
  std::uint64_t exhausted = 0;
  long stuck_steps = 0;
  for (int i = 0; i < 40; ++i) {
    OscillatorParams p = test::random_sticking_seat(random, FrictionModel::stick_slip);
    const std::uint64_t floor_seed = random.next();
    hold_random_seat_at_the_threshold<float, CoulombStickSlip>(p, floor_seed, most_events,
                                                               exhausted, stuck_steps);
    hold_random_seat_at_the_threshold<double, CoulombStickSlip>(p, floor_seed, most_events,
                                                                exhausted, stuck_steps);
    p.model = FrictionModel::stribeck;
    hold_random_seat_at_the_threshold<float, StribeckStickSlip>(p, floor_seed, most_events,
                                                                exhausted, stuck_steps);
    hold_random_seat_at_the_threshold<double, StribeckStickSlip>(p, floor_seed, most_events,
                                                                 exhausted, stuck_steps);
  }
  CHECK_EQUAL(0u, exhausted);
  CHECK_TRUE(most_events <= kMaxEventsOfTheExactSolutionPerStep);
  CHECK_TRUE(stuck_steps > 15000);  // the threshold phases held the seats
  test::note_margin("most events in a step at the threshold, random seats", most_events,
                    double(kMaxEventsOfTheExactSolutionPerStep));
}
