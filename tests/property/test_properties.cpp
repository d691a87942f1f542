// Property tests: random parameters and inputs (fixed seeds, hundreds of cases per property).
#include <cfloat>
#include <cmath>
#include <limits>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "property/property_support.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/models/dispatch.hpp"

using namespace stickslip;

namespace {

constexpr int kCasesPerLaw = 100;
constexpr std::size_t kSteps = 2000;

SimpleString describe(const char* type, const OscillatorParams& p, int trial) {
  return StringFromFormat(
      "%s %s/%s %s case %d: m=%.6g k=%.6g b=%.6g F_fk=%.6g F_fs=%.6g v_S=%.3g "
      "c=%.6g dt=%.6g",
      type, model_name(p.model), smoothing_name(p.smoothing), integrator_name(p.integrator), trial,
      p.mass_kg, p.stiffness_n_per_m, p.damping_ns_per_m, p.kinetic_friction_n, p.static_friction_n,
      p.stribeck_velocity_m_per_s, p.smoothing_constant_s_per_m, p.dt_s);
}

// The energy bound each integrator documents with a_u = 0 (tests/core/test_passivity.cpp):
//   exact       no rise in any step beyond rounding (1e-12 E0);
//   symplectic  E <= E0 (1 + w h/2)/(1 - w h/2): the scheme conserves a modified energy whose
//               ratio to E lies between 1 -+ w h/2; damping and friction only remove energy;
//   rk4         E <= 1.01 E0 (dissipative undamped; damped, a transient within 1 %);
//   euler       E <= 2 E0 wherever configure() accepts it.
double energy_bound(const OscillatorParams& p) {
  const double half = 0.5 * std::sqrt(p.stiffness_n_per_m / p.mass_kg) * p.dt_s;
  switch (p.integrator) {
    case Integrator::symplectic:
      return (1.0 + half) / (1.0 - half) * (1.0 + 1e-9);
    case Integrator::rk4:
      return 1.01;
    case Integrator::euler:
      return 2.0;
    case Integrator::exact:
      break;
  }
  return 1.0 + 1e-12;
}

}  // namespace

TEST_GROUP(Properties){};

// Passivity: with a_u = 0 from a random state the energy never rises beyond the integrator's
// bound; for the exact integrator not in any single step (beyond rounding), every law.
TEST(Properties, PassiveWithoutInput) {
  test::SplitMix64 random(0x5eed0001);
  int accepted = 0, exact_cases = 0;
  double worst_exact_rise = 0.0;
  for (Integrator integrator : test::kAllIntegrators) {
    for (FrictionModel model : test::kAllModels) {
      for (int trial = 0; trial < kCasesPerLaw; ++trial) {
        const OscillatorParams p = test::random_params(random, model, integrator);
        const double x0 = random.uniform(-0.2, 0.2), v0 = random.uniform(-1.0, 1.0);
        with_oscillator<double>(p, [&](auto& seat) {
          const bool ok = seat.configure(p).ok();
          if (integrator == Integrator::exact)
            CHECK_TEXT(ok, describe("double", p, trial).asCharString());
          if (!ok) return 0;
          ++accepted;
          seat.reset(x0, v0, 0.0);
          const double e0 = test::energy_j(p, x0, v0);
          const double bound = energy_bound(p) * e0;
          double previous = e0;
          for (std::size_t n = 1; n <= kSteps; ++n) {
            const auto out = seat.step(0.0);
            const double e = test::energy_j(p, out.x_r_m, out.v_r_m_per_s);
            if (integrator == Integrator::exact) {
              const double rise = (e - previous) / e0;
              if (rise > worst_exact_rise) worst_exact_rise = rise;
              if (!(rise <= 1e-12))
                FAIL(StringFromFormat("%s: step %zu raised E by %.3e E0",
                                      describe("double", p, trial).asCharString(), n, rise)
                         .asCharString());
            } else if (!(e <= bound)) {
              FAIL(StringFromFormat("%s: step %zu E = %.6g E0 > bound %.6g E0",
                                    describe("double", p, trial).asCharString(), n, e / e0,
                                    bound / e0)
                       .asCharString());
            }
            previous = e;
          }
          if (integrator == Integrator::exact) ++exact_cases;
          return 0;
        });
      }
    }
  }
  LONGS_EQUAL(5 * kCasesPerLaw, exact_cases);
  CHECK(accepted > 2 * 5 * kCasesPerLaw);  // the explicit schemes were exercised too
  test::note_margin("exact: worst energy rise per step / E0", worst_exact_rise, 1e-12);
}

// Stick-slip and Stribeck: a stuck seat whose limit force stays within F_fs over the whole step
// (at both ends, F_L being linear in it, with the rounding of F_L itself as margin) does not move:
// x_r is unchanged to the bit, v_r = 0, the whole step is stuck. And whenever the seat is stuck,
// a_x equals a_u exactly. Float and double, every integrator.
template <typename T>
void check_sticking_properties(std::uint64_t seed, int& held_steps, int& stuck_samples) {
  test::SplitMix64 random(seed);
  constexpr double eps = static_cast<double>(std::numeric_limits<T>::epsilon());
  for (Integrator integrator : test::kAllIntegrators) {
    for (FrictionModel model : {FrictionModel::stick_slip, FrictionModel::stribeck}) {
      for (int trial = 0; trial < kCasesPerLaw; ++trial) {
        const OscillatorParams p = test::random_params(random, model, integrator);
        const std::vector<double> input = test::random_input(random, p.dt_s, kSteps);
        with_oscillator<T>(p, [&](auto& seat) {
          if (!seat.configure(p).ok()) return 0;
          seat.reset(T(0), T(0), static_cast<T>(input[0]));
          const double m = static_cast<double>(static_cast<T>(p.mass_kg));
          const double k = static_cast<double>(static_cast<T>(p.stiffness_n_per_m));
          const double f_fs = static_cast<double>(static_cast<T>(p.static_friction_n));
          auto within = [&](double a, double x) {
            const double limit = std::fabs(m * a + k * x);
            return limit + 8.0 * eps * (std::fabs(m * a) + std::fabs(k * x)) <= f_fs;
          };
          for (std::size_t n = 1; n <= kSteps; ++n) {
            const T a0 = static_cast<T>(input[n - 1]), a1 = static_cast<T>(input[n]);
            const bool was_stuck = seat.stuck();
            const T x_before = seat.x_r();
            const auto out = seat.step(a1);
            if (was_stuck && within(static_cast<double>(a0), static_cast<double>(x_before)) &&
                within(static_cast<double>(a1), static_cast<double>(x_before))) {
              ++held_steps;
              const bool held = out.stuck && out.x_r_m == x_before && out.v_r_m_per_s == T(0) &&
                                out.stuck_fraction == T(1);
              if (!held)
                FAIL(StringFromFormat(
                         "%s step %zu: moved while |F_L| <= F_fs (x %.9g -> %.9g)",
                         describe(sizeof(T) == 4 ? "float" : "double", p, trial).asCharString(), n,
                         static_cast<double>(x_before), static_cast<double>(out.x_r_m))
                         .asCharString());
            }
            if (out.stuck) {
              ++stuck_samples;
              if (!(out.a_x_m_per_s2 == a1 && out.v_r_m_per_s == T(0)))
                FAIL(StringFromFormat(
                         "%s step %zu: stuck but a_x = %.9g != a_u = %.9g",
                         describe(sizeof(T) == 4 ? "float" : "double", p, trial).asCharString(), n,
                         static_cast<double>(out.a_x_m_per_s2), static_cast<double>(a1))
                         .asCharString());
            }
          }
          return 0;
        });
      }
    }
  }
}

TEST(Properties, StuckSeatNeverMovesWithinStaticFrictionAndMovesWithTheFloor) {
  int held = 0, stuck = 0;
  check_sticking_properties<double>(0x5eed0002, held, stuck);
  check_sticking_properties<float>(0x5eed0003, held, stuck);
  CHECK(held > 100000);  // both properties were exercised, many times
  CHECK(stuck > held);
  test::note_margin("steps held within F_fs", held, 0.0);
}

// Two runs of the same scene agree bit for bit, and so does a copy of the oscillator taken in the
// middle of a run (the state is all in the object: no hidden global or static).
template <typename T>
int check_reproducible(std::uint64_t seed) {
  test::SplitMix64 random(seed);
  int compared = 0;
  for (Integrator integrator : test::kAllIntegrators) {
    for (FrictionModel model : test::kAllModels) {
      for (int trial = 0; trial < kCasesPerLaw / 2; ++trial) {
        const OscillatorParams p = test::random_params(random, model, integrator);
        const std::vector<double> input = test::random_input(random, p.dt_s, kSteps);
        with_oscillator<T>(p, [&](auto& first) {
          auto second = first;
          if (!first.configure(p).ok()) return 0;
          CHECK(second.configure(p).ok());
          first.reset(T(0), T(0), static_cast<T>(input[0]));
          second.reset(T(0), T(0), static_cast<T>(input[0]));
          auto copy = first;
          for (std::size_t n = 1; n <= kSteps; ++n) {
            if (n == kSteps / 2) copy = first;
            const auto a = first.step(static_cast<T>(input[n]));
            const auto b = second.step(static_cast<T>(input[n]));
            const bool same_copy =
                n < kSteps / 2 || test::same_bits(a, copy.step(static_cast<T>(input[n])));
            if (!test::same_bits(a, b) || !same_copy)
              FAIL(StringFromFormat(
                       "%s step %zu: runs differ",
                       describe(sizeof(T) == 4 ? "float" : "double", p, trial).asCharString(), n)
                       .asCharString());
          }
          ++compared;
          return 0;
        });
      }
    }
  }
  return compared;
}

TEST(Properties, TwoRunsAgreeBitForBit) {
  const int compared =
      check_reproducible<double>(0x5eed0004) + check_reproducible<float>(0x5eed0005);
  CHECK(compared > 500);
}

// Float vs double, linear seat, exact integrator, damping ratio 0.1..2: the float run differs from
// the double run by rounding only, and the map forgets old errors. Each float step commits a
// relative error of a few epsilon (eight multiply-adds, coefficients rounded to float) of the
// state scale X = max|x_r| + max|a_u|/omega0^2 (the input's share of x_r); the homogeneous map
// damps it by the spectral radius rho per step, so the errors add up over at most about 1/(1-rho)
// steps:
//   |x_float - x_double| <= 32 eps_float X min(n, 2/(1 - rho)).
// 32 = 8 roundings per step times a factor 4 for non-normality near critical damping.
TEST(Properties, FloatFollowsDoubleWithinRoundingBound) {
  test::SplitMix64 random(0x5eed0006);
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    OscillatorParams p = test::random_params(random, FrictionModel::linear, Integrator::exact);
    const double omega0 = std::sqrt(p.stiffness_n_per_m / p.mass_kg);
    p.damping_ns_per_m =
        random.uniform(0.1, 2.0) * 2.0 * std::sqrt(p.stiffness_n_per_m * p.mass_kg);
    const std::vector<double> input = test::random_input(random, p.dt_s, kSteps);
    Oscillator<double, NoFriction> wide;
    Oscillator<float, NoFriction> narrow;
    CHECK(wide.configure(p).ok());
    CHECK(narrow.configure(p).ok());
    const double rho =
        spectral_radius(linear_step_map(Integrator::exact, p.stiffness_n_per_m / p.mass_kg,
                                        p.damping_ns_per_m / p.mass_kg, p.dt_s));
    wide.reset(0.0, 0.0, input[0]);
    narrow.reset(0.0f, 0.0f, static_cast<float>(input[0]));
    double max_x = 0.0, max_a = std::fabs(input[0]), max_diff = 0.0;
    for (std::size_t n = 1; n <= kSteps; ++n) {
      const auto d = wide.step(input[n]);
      const auto f = narrow.step(static_cast<float>(input[n]));
      max_x = std::fmax(max_x, std::fabs(d.x_r_m));
      max_a = std::fmax(max_a, std::fabs(input[n]));
      max_diff = std::fmax(max_diff, std::fabs(static_cast<double>(f.x_r_m) - d.x_r_m));
    }
    const double scale = max_x + max_a / (omega0 * omega0);
    const double memory = std::fmin(static_cast<double>(kSteps), 2.0 / (1.0 - rho));
    const double bound = 32.0 * static_cast<double>(FLT_EPSILON) * scale * memory;
    CHECK_TEXT(max_diff <= bound,
               StringFromFormat("%s: |x_f - x_d| = %.3e > %.3e",
                                describe("float", p, trial).asCharString(), max_diff, bound)
                   .asCharString());
    worst = std::fmax(worst, max_diff / bound);
  }
  test::note_margin("float vs double: worst |dx| / bound", worst, 1.0);
}
