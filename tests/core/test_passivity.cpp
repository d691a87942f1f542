// Passivity with no input (a_u = 0): friction and damping can only take energy out.
//
// E = 1/2 m v_r^2 + 1/2 k x_r^2 obeys dE/dt = -b v^2 - F_f v <= 0 for every law, because every
// friction force opposes v_r (or is zero). The exact integrator holds the friction of the step
// start and re-samples it where v_r changes sign, which keeps this property step by step: E must
// never increase beyond rounding. The explicit integrators are not passive but must stay bounded
// whenever configure() accepts them.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/models/dispatch.hpp"

using namespace stickslip;

namespace {

constexpr double kKineticN = 40.0;
constexpr double kStaticN = 50.0;
constexpr double kRoundingTolerance = 1e-12;  // of the initial energy, per step

struct LawCase {
  const char* name;
  FrictionModel model;
  SmoothingLaw smoothing;
  double damping_ns_per_m;
};

const LawCase kLaws[] = {
    {"linear b=504", FrictionModel::linear, SmoothingLaw::tanh, test::kDampingNsPerM},
    {"linear b=0", FrictionModel::linear, SmoothingLaw::tanh, 0.0},
    {"signum", FrictionModel::signum, SmoothingLaw::tanh, test::kDampingNsPerM},
    {"signum b=0", FrictionModel::signum, SmoothingLaw::tanh, 0.0},
    {"smooth atan", FrictionModel::smooth, SmoothingLaw::atan, test::kDampingNsPerM},
    {"smooth tanh", FrictionModel::smooth, SmoothingLaw::tanh, test::kDampingNsPerM},
    {"smooth erf", FrictionModel::smooth, SmoothingLaw::erf, test::kDampingNsPerM},
    {"smooth rational", FrictionModel::smooth, SmoothingLaw::rational, 0.0},
    {"stick-slip", FrictionModel::stick_slip, SmoothingLaw::tanh, test::kDampingNsPerM},
    {"stick-slip b=0", FrictionModel::stick_slip, SmoothingLaw::tanh, 0.0},
    {"stribeck", FrictionModel::stribeck, SmoothingLaw::tanh, test::kDampingNsPerM},
    {"stribeck b=0", FrictionModel::stribeck, SmoothingLaw::tanh, 0.0},
};

OscillatorParams law_params(const LawCase& law, Integrator integrator, double dt_s) {
  OscillatorParams p = test::reference_params(law.model, integrator, dt_s, law.damping_ns_per_m);
  p.kinetic_friction_n = kKineticN;
  p.static_friction_n = kStaticN;
  p.smoothing = law.smoothing;
  p.smoothing_constant_s_per_m = 1000.0;
  p.stribeck_velocity_m_per_s = 0.01;
  return p;
}

struct EnergyTrace {
  bool configured = false;
  double initial_j = 0.0;
  double max_rise_per_step = 0.0;  // max (E[n+1] - E[n]) / E[0]
  double max_ratio = 0.0;          // max E[n] / E[0]
  double final_ratio = 0.0;
};

// Free motion from (x0, v0) with a_u = 0 for `steps` steps, through the run-time dispatch.
EnergyTrace trace_energy(const OscillatorParams& params, double x0, double v0, long steps) {
  return with_oscillator<double>(params, [&](auto& seat) {
    EnergyTrace trace;
    const auto config = seat.configure(params);
    if (!config.ok()) return trace;
    trace.configured = true;
    seat.reset(x0, v0, 0.0);
    const double m = params.mass_kg, k = params.stiffness_n_per_m;
    trace.initial_j = test::mechanical_energy_j(m, k, x0, v0);
    double previous = trace.initial_j;
    for (long n = 0; n < steps; ++n) {
      const auto out = seat.step(0.0);
      const double e = test::mechanical_energy_j(m, k, out.x_r_m, out.v_r_m_per_s);
      trace.max_rise_per_step = std::max(trace.max_rise_per_step, (e - previous) / trace.initial_j);
      trace.max_ratio = std::max(trace.max_ratio, e / trace.initial_j);
      previous = e;
    }
    trace.final_ratio = previous / trace.initial_j;
    CHECK_EQUAL(0u, seat.state_resets());
    return trace;
  });
}

// Random initial states of a few joules to ~20 J (|x0| up to 5 cm, |v0| up to 0.3 m/s).
void random_state(test::SplitMix64& random, double& x0, double& v0) {
  x0 = random.uniform(0.005, 0.05) * (random.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0);
  v0 = random.uniform(-0.3, 0.3);
}

}  // namespace

TEST_GROUP(Passivity){};

// Exact integrator: E never increases from step to step (1e-12 E0 rounding), for every friction
// law, with and without damping, over long runs from random states and several steps.
TEST(Passivity, ExactIntegratorNeverGainsEnergyWithAnyFrictionLaw) {
  test::SplitMix64 random(20240611);
  const double steps_s[] = {1e-3, 1e-2, 0.05};
  double worst_rise = -1.0;
  for (double dt : steps_s) {
    for (const LawCase& law : kLaws) {
      for (int trial = 0; trial < 6; ++trial) {
        double x0 = 0.0, v0 = 0.0;
        random_state(random, x0, v0);
        // 40 s of motion: thousands of cycles at dt = 1 ms, long enough to settle and chatter.
        const long steps = std::lround(40.0 / dt);
        const EnergyTrace t = trace_energy(law_params(law, Integrator::exact, dt), x0, v0, steps);
        CHECK_TEXT(t.configured, law.name);
        CHECK_TEXT(t.max_rise_per_step <= kRoundingTolerance,
                   StringFromFormat("%s dt = %g x0 = %g v0 = %g: energy rose by %.3e E0 in a step",
                                    law.name, dt, x0, v0, t.max_rise_per_step)
                       .asCharString());
        worst_rise = std::max(worst_rise, t.max_rise_per_step);
        if (law.model != FrictionModel::linear || law.damping_ns_per_m > 0.0) {
          CHECK_TEXT(t.final_ratio < 1.0, law.name);  // and it does dissipate
        }
      }
    }
  }
  test::note_margin("exact: worst energy rise per step / E0", worst_rise, kRoundingTolerance);
}

// b = 0 and no friction: the exact integrator conserves E (to rounding) rather than merely not
// gaining it; guards against a trivially dissipative "exact" map.
TEST(Passivity, ExactUndampedLinearSeatConservesEnergy) {
  const EnergyTrace t =
      trace_energy(law_params(kLaws[1], Integrator::exact, 1e-3), 0.03, 0.1, 100000);
  DOUBLES_EQUAL(1.0, t.final_ratio, 1e-10);
  DOUBLES_EQUAL(1.0, t.max_ratio, 1e-10);
}

// Every block map of the exact integrator scales phase-space area by exp(-b h/m) to the rounding
// of its four coefficients, eps (|xx vv| + |xv vx|), up to stops stiff enough for omega0 dt = 2.1
// (undamped, a larger error would make the energy drift by it every step). Scaling and squaring
// on the unbalanced matrix squared log2(omega0^2 h) times: 2.9e-15 off at omega0 dt = pi/2.
TEST(Passivity, ExactMapsScaleAreaByTheirExactDeterminantToRoundingOnStiffSeats) {
  const double eps = std::numeric_limits<double>::epsilon();
  int maps = 0;
  for (const double omega_dt : {0.01, 0.5, 1.0, 1.4, 1.5707963267948966, 2.1}) {
    for (const double damping : {0.0, 504.0, 20000.0}) {
      OscillatorParams p =
          test::reference_params(FrictionModel::linear, Integrator::exact, 1e-3, damping);
      p.stiffness_n_per_m = p.mass_kg * (omega_dt / p.dt_s) * (omega_dt / p.dt_s);
      DiscreteModel model;
      CHECK_TRUE(discretise(p, model).ok());
      for (int level = 0; level < kMapLevels; ++level) {
        const StepMap<double>& m = model.maps[level];
        using Wide = long double;
        const Wide h = std::ldexp(Wide(p.dt_s), -level);
        const Wide exact = std::exp(-Wide(damping) / Wide(p.mass_kg) * h);
        const Wide determinant = Wide(m.xx) * Wide(m.vv) - Wide(m.xv) * Wide(m.vx);
        const double bound = eps * (std::fabs(m.xx * m.vv) + std::fabs(m.xv * m.vx)) * (1.0 + 1e-6);
        CHECK(static_cast<double>(std::fabs(determinant - exact)) <= bound);
        ++maps;
      }
    }
  }
  CHECK_EQUAL(6 * 3 * kMapLevels, maps);
}

// Double's maps (NearIdentityStepMap) against the closed form of an undamped seat: the identity
// split off the diagonal where xx = vv = cos(omega0 h) > 1/2, and then xx - 1 = vv - 1 =
// -2 sin^2(omega0 h / 2), else xx = vv = cos(omega0 h); xv = sin(omega0 h) / omega0, vx = -omega0
// sin(omega0 h); each to 2 eps of itself. xx - 1 formed from a rounded xx would be off by up to
// eps / 2 against a value of (omega0 h)^2 / 2: 1 % of it at the finest level of omega0 dt = 0.01.
// omega0 dt = 1.2 and 2.1 keep the plain diagonal on their coarsest levels.
TEST(Passivity, ExactMapsNearTheIdentityKeepTheirDiagonalToADoublesPrecision) {
  const double eps = std::numeric_limits<double>::epsilon();
  int maps = 0, split = 0;
  for (const double omega_dt : {0.01, 0.5, 1.0, 1.2, 2.1}) {
    OscillatorParams p =
        test::reference_params(FrictionModel::linear, Integrator::exact, 1e-3, 0.0);
    p.stiffness_n_per_m = p.mass_kg * (omega_dt / p.dt_s) * (omega_dt / p.dt_s);
    DiscreteModel model;
    CHECK_TRUE(discretise(p, model).ok());
    using Wide = long double;
    const Wide omega = std::sqrt(Wide(p.stiffness_n_per_m) / Wide(p.mass_kg));
    for (int level = 0; level < kMapLevels; ++level) {
      const NearIdentityStepMap<double> near = near_identity_step_map(p, level);
      const StepMap<double>& m = near.rest;
      const Wide h = std::ldexp(Wide(p.dt_s), -level);
      const Wide half = std::sin(omega * h / 2);
      const bool near_one = std::cos(omega * h) > 0.5L;
      const Wide diagonal = near_one ? -2 * half * half : std::cos(omega * h);
      const Wide xv = std::sin(omega * h) / omega, vx = -omega * std::sin(omega * h);
      CHECK_EQUAL(near_one ? 1.0 : 0.0, near.identity_x);
      CHECK_EQUAL(near_one ? 1.0 : 0.0, near.identity_v);
      CHECK(std::fabs(Wide(m.xx) - diagonal) <= 2 * eps * std::fabs(diagonal));
      CHECK(std::fabs(Wide(m.vv) - diagonal) <= 2 * eps * std::fabs(diagonal));
      CHECK(std::fabs(Wide(m.xv) - xv) <= 2 * eps * std::fabs(xv));
      CHECK(std::fabs(Wide(m.vx) - vx) <= 2 * eps * std::fabs(vx));
      ++maps;
      split += near_one ? 1 : 0;
    }
  }
  CHECK_EQUAL(5 * kMapLevels, maps);
  CHECK_EQUAL(5 * kMapLevels - 3, split);  // 1.2: level 0; 2.1: levels 0 and 1 (cos 1.05 = 0.498)
}

// Symplectic and RK4 with b > 0 inside their stability limits: E never exceeds 1.01 E0, from
// random states and from a large one (0.5 m, 1 m/s), at 1 ms, 10 ms and 50 ms.
TEST(Passivity, DampedSymplecticAndRk4StayWithinOnePercentOfInitialEnergy) {
  test::SplitMix64 random(77);
  double worst = 0.0;
  int accepted = 0;
  for (double dt : {1e-3, 1e-2, 0.05}) {
    for (Integrator integrator : {Integrator::symplectic, Integrator::rk4}) {
      for (const LawCase& law : kLaws) {
        if (law.damping_ns_per_m == 0.0) continue;
        for (int trial = 0; trial < 5; ++trial) {
          double x0 = 0.5, v0 = 1.0;
          if (trial > 0) random_state(random, x0, v0);
          const EnergyTrace t =
              trace_energy(law_params(law, integrator, dt), x0, v0, std::lround(20.0 / dt));
          if (!t.configured) continue;  // e.g. a stiff smoothed law at 10 ms
          ++accepted;
          CHECK_TEXT(t.max_ratio <= 1.01,
                     StringFromFormat("%s %s dt = %g x0 = %g v0 = %g: E reached %.6f E0", law.name,
                                      integrator_name(integrator), dt, x0, v0, t.max_ratio)
                         .asCharString());
          worst = std::max(worst, t.max_ratio);
        }
      }
    }
  }
  CHECK(accepted > 100);
  test::note_margin("damped symplectic/rk4 max E/E0", worst, 1.01);
}

// b = 0: symplectic Euler conserves I = v^2 + w^2 x^2 - h w^2 x v exactly (linear, no input), so
// E may swing by the ratio of the eigenvalues 1 -+ w h/2 of that form but never beyond
//   E <= E0 (1 + w h/2) / (1 - w h/2)      (1.0115 at 1 ms, 1.80 at 50 ms);
// friction only takes energy out. RK4 is dissipative for the undamped oscillator (|R(i w h)| < 1
// and normal in (w x, v)): E <= E0. Zero and small friction make the sticking laws' event
// handling (reversals at every v_r = 0) carry the motion.
TEST(Passivity, UndampedSymplecticAndRk4StayBounded) {
  struct Undamped {
    const char* name;
    FrictionModel model;
    double kinetic_n, static_n;
  };
  const Undamped laws[] = {
      {"linear", FrictionModel::linear, 0.0, 0.0},
      {"signum 1 N", FrictionModel::signum, 1.0, 1.0},
      {"smooth 1 N", FrictionModel::smooth, 1.0, 1.0},
      {"stick-slip 0 N", FrictionModel::stick_slip, 0.0, 0.0},
      {"stick-slip 1 N", FrictionModel::stick_slip, 1.0, 1.0},
      {"stick-slip 40 N", FrictionModel::stick_slip, 40.0, 50.0},
      {"stribeck 0 N", FrictionModel::stribeck, 0.0, 0.0},
      {"stribeck 1 N", FrictionModel::stribeck, 1.0, 1.5},
  };
  const double omega0 = test::natural_frequency_rad_s(test::kMassKg, test::kStiffnessNPerM);
  SimpleString failures;
  int failed = 0;
  double worst_symplectic = 0.0;
  for (double dt : {1e-3, 1e-2, 0.05}) {
    const double half = 0.5 * omega0 * dt;
    const double symplectic_bound = (1.0 + half) / (1.0 - half) * (1.0 + 1e-9);
    for (Integrator integrator : {Integrator::symplectic, Integrator::rk4}) {
      const double bound = integrator == Integrator::rk4 ? 1.0 + 1e-9 : symplectic_bound;
      for (const Undamped& law : laws) {
        OscillatorParams p = test::reference_params(law.model, integrator, dt, 0.0);
        p.kinetic_friction_n = law.kinetic_n;
        p.static_friction_n = law.static_n;
        p.smoothing_constant_s_per_m = 100.0;
        const bool sticking =
            law.model == FrictionModel::stick_slip || law.model == FrictionModel::stribeck;
        if (integrator == Integrator::symplectic && sticking) {
          // Restarting the staggered scheme at reversals pumps energy with nothing to absorb it:
          // configure() refuses this combination without damping, naming damping and the limit.
          ConfigResult refused;
          with_oscillator<double>(p, [&](auto& seat) { refused = seat.configure(p); });
          CHECK_TEXT(refused.status == Status::unstable, law.name);
          STRCMP_CONTAINS("damping_ns_per_m:", refused.message.c_str());
          STRCMP_CONTAINS("stability limit", refused.message.c_str());
          continue;
        }
        const EnergyTrace t = trace_energy(p, 0.5, 0.0, std::lround(40.0 / dt));
        CHECK_TEXT(t.configured, law.name);
        if (integrator == Integrator::symplectic)
          worst_symplectic = std::max(worst_symplectic, t.max_ratio / bound);
        if (!(t.max_ratio <= bound) && failed++ < 16)
          failures +=
              StringFromFormat("\n\t  %s %s dt = %g: E reached %.4g E0 (bound %.4g)", law.name,
                               integrator_name(integrator), dt, t.max_ratio, bound);
      }
    }
  }
  CHECK_TEXT(failed == 0, StringFromFormat("%d undamped scenes gained energy:%s", failed,
                                           failures.asCharString())
                              .asCharString());
  test::note_margin("undamped symplectic max E / bound", worst_symplectic, 1.0);
}

// Explicit Euler: wherever configure() accepts it the energy stays bounded, from random states and
// from a large one (0.5 m, 1 m/s), and decays in the long run where the equilibrium is unique.
TEST(Passivity, ExplicitEulerIsBoundedWheneverAccepted) {
  test::SplitMix64 random(5);
  const double steps_s[] = {1e-4, 1e-3, 5e-3, 1e-2, 2e-2, 4e-2};
  double worst = 0.0;
  int accepted = 0;
  SimpleString failures;
  int failed = 0;
  for (double dt : steps_s) {
    for (const LawCase& law : kLaws) {
      for (int trial = 0; trial < 2; ++trial) {
        double x0 = 0.5, v0 = 1.0;
        if (trial > 0) random_state(random, x0, v0);
        const EnergyTrace t =
            trace_energy(law_params(law, Integrator::euler, dt), x0, v0, std::lround(40.0 / dt));
        if (!t.configured) continue;
        ++accepted;
        // Linear and smoothed laws have the single equilibrium x = 0 and must decay to it; the
        // others may stop anywhere in their static band |k x| <= F_f.
        const bool unique_equilibrium =
            law.model == FrictionModel::linear || law.model == FrictionModel::smooth;
        const bool ok = t.max_ratio <= 2.0 && (!unique_equilibrium || t.final_ratio < 1e-2);
        if (!ok && failed++ < 8)
          failures += StringFromFormat(
              "\n\t  %s euler dt = %g x0 = %g v0 = %g: max E %.4g E0, final %.4g E0", law.name, dt,
              x0, v0, t.max_ratio, t.final_ratio);
        worst = std::max(worst, t.max_ratio);
      }
    }
  }
  CHECK_TEXT(failed == 0, StringFromFormat("%d accepted Euler scenes unbounded or not decaying:%s",
                                           failed, failures.asCharString())
                              .asCharString());
  CHECK(accepted > 20);  // the loop did test something
  test::note_margin("euler max E/E0", worst, 2.0);
}
