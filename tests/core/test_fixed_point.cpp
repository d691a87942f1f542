// The fixed-point scalar (core/fixed_point.hpp): rounding and saturation of every operation
// against exact integer references, the flag never silent; the oscillator with it against double;
// configure() refusing scenes that would not fit, by name.
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "fixed_point_checks.hpp"
#include "oracles.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;

namespace {

__extension__ typedef __int128 Int128;

constexpr std::int64_t kMax = INT64_MAX;

// round(a * b / 2^40), ties away from zero, from the compiler's 128-bit integers.
std::int64_t reference_product(std::int64_t a, std::int64_t b) {
  return static_cast<std::int64_t>(test::rounded_product<40>(Int128{a}, Int128{b}));
}

// Q23.40 runs the oscillator on the SI scene itself (fixed_point_checks.hpp).
struct Q23_40 {
  using Scalar = Fixed;
  template <typename Law>
  using Seat = Oscillator<Fixed, Law>;
  static constexpr const char* kName = "fixed";
  // The default ranges.
  static OscillatorParams params(FrictionModel model, Integrator integrator) {
    return test::reference_params(model, integrator, 1e-3);
  }
  template <typename S>
  static S& model(S& seat) {
    return seat;
  }
  template <typename S>
  static Fixed input(S&, double a_m_per_s2) {
    return Fixed(a_m_per_s2);
  }
  template <typename S>
  static double metres(S&, Fixed x_r) {
    return x_r.to_double();
  }
  template <typename S>
  static double acceleration(S&, Fixed a_x) {
    return a_x.to_double();
  }
};

}  // namespace

TEST_GROUP(FixedPointArithmetic){void setup() override{(void)take_fixed_point_saturation();
}
}
;

TEST(FixedPointArithmetic, ProductRoundsToNearestTiesAwayFromZero) {
  const Fixed half(0.5), quarter(0.25);
  LONGS_EQUAL(2, (Fixed::from_raw(3) * half).raw());     // 1.5 ulp -> 2
  LONGS_EQUAL(-2, (Fixed::from_raw(-3) * half).raw());   // symmetric
  LONGS_EQUAL(1, (Fixed::from_raw(1) * half).raw());     // 0.5 -> 1
  LONGS_EQUAL(1, (Fixed::from_raw(5) * quarter).raw());  // 1.25 -> 1
  LONGS_EQUAL(2, (Fixed::from_raw(7) * quarter).raw());  // 1.75 -> 2
  LONGS_EQUAL(0, (Fixed::from_raw(1) * quarter).raw());  // 0.25 -> 0
  CHECK_FALSE(fixed_point_saturated());
}

TEST(FixedPointArithmetic, ProductEqualsExact128BitReference) {
  test::SplitMix64 random(5);
  for (int i = 0; i < 20000; ++i) {
    // Magnitudes from 2^0 to 2^62 ulp, both signs; products that fit.
    const int bits_a = static_cast<int>(random.next() % 62), bits_b = 62 - bits_a;
    std::int64_t a = static_cast<std::int64_t>(random.next() >> (64 - bits_a - 1));
    std::int64_t b = static_cast<std::int64_t>(random.next() >> (64 - (bits_b > 40 ? 40 : bits_b)));
    if (random.next() & 1u) a = -a;
    if (random.next() & 1u) b = -b;
    const Fixed product = Fixed::from_raw(a) * Fixed::from_raw(b);
    const std::int64_t expected = reference_product(a, b);
    if (product.raw() != expected) {
      FAIL(StringFromFormat("%lld * %lld: %lld, expected %lld", static_cast<long long>(a),
                            static_cast<long long>(b), static_cast<long long>(product.raw()),
                            static_cast<long long>(expected))
               .asCharString());
    }
  }
  CHECK_FALSE(fixed_point_saturated());
}

TEST(FixedPointArithmetic, OverflowSaturatesAndSetsTheStickyFlag) {
  const Fixed max = Fixed::from_raw(kMax), one(1);
  // Sum.
  LONGS_EQUAL(kMax, (max + one).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax, (-max - one).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  // Product: 4e6 * 4e6 = 1.6e13 >> 8.4e6.
  LONGS_EQUAL(kMax, (Fixed(4e6) * Fixed(4e6)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax, (Fixed(-4e6) * Fixed(4e6)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  // Quotient.
  LONGS_EQUAL(kMax, (Fixed(1e6) / Fixed::from_raw(1)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax, (Fixed(-3) / Fixed(0)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(0, (Fixed(0) / Fixed(0)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  // Conversions.
  LONGS_EQUAL(kMax, Fixed(1e7).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(0, Fixed(std::nan("")).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(kMax, Fixed(1 << 24).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(0u, static_cast<unsigned>(Fixed(-1)));
  CHECK_TRUE(take_fixed_point_saturation());
  // Sticky: set by one operation, kept through many that do not saturate.
  Fixed sum = max + one;
  for (int i = 0; i < 100; ++i) sum = sum * Fixed(0.5);
  CHECK_TRUE(fixed_point_saturated());
  CHECK_TRUE(take_fixed_point_saturation());
  CHECK_FALSE(fixed_point_saturated());
  // At the limit without crossing it: no flag.
  LONGS_EQUAL(kMax, (max - one + one).raw());
  CHECK_FALSE(fixed_point_saturated());
}

TEST(FixedPointArithmetic, ConversionsRoundToNearest) {
  LONGS_EQUAL(1, Fixed(0.6 / 1099511627776.0).raw());  // 0.6 ulp -> 1
  LONGS_EQUAL(-1, Fixed(-0.6 / 1099511627776.0).raw());
  LONGS_EQUAL(1, Fixed(0.5 / 1099511627776.0).raw());  // tie away from zero
  LONGS_EQUAL(0, Fixed(0.4 / 1099511627776.0).raw());
  DOUBLES_EQUAL(88.4, Fixed(88.4).to_double(), 1e-12);
  LONGS_EQUAL(3u, static_cast<unsigned>(Fixed(3.99)));
  CHECK_TRUE(Fixed(3) == Fixed(3.0));
  CHECK_FALSE(fixed_point_saturated());
}

TEST(FixedPointArithmetic, QuotientWithinTwoToTheMinus29) {
  test::SplitMix64 random(11);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double a =
        random.uniform(-1.0, 1.0) * std::ldexp(1.0, static_cast<int>(random.next() % 30) - 20);
    const double b =
        random.uniform(-1.0, 1.0) * std::ldexp(1.0, static_cast<int>(random.next() % 30) - 20);
    const Fixed fa(a), fb(b);
    if (fb.raw() == 0) continue;
    const double exact = fa.to_double() / fb.to_double();
    if (!(std::fabs(exact) < 1e6)) continue;
    const double got = (fa / fb).to_double();
    const double error = std::fabs(got - exact);
    const double allowed = std::ldexp(std::fabs(exact), -29) + Fixed::resolution();
    if (error > allowed) {
      FAIL(StringFromFormat("%.17g / %.17g = %.17g, got %.17g", fa.to_double(), fb.to_double(),
                            exact, got)
               .asCharString());
    }
    const double relative = std::fabs(exact) > 1e-3 ? error / std::fabs(exact) : 0.0;
    if (relative > worst) worst = relative;
  }
  test::note_margin("fixed-point quotient relative error", worst, std::ldexp(1.0, -29));
  CHECK_FALSE(fixed_point_saturated());
}

TEST_GROUP(FixedPointOscillator){void setup() override{(void)take_fixed_point_saturation();
}
}
;

TEST(FixedPointOscillator, StickSlipAgreesWithDoubleOnTheLorryScene) {
  test::check_stick_slip_agrees_with_double_on_the_lorry_scene<Q23_40>();
}

TEST(FixedPointOscillator, HeldLawsAgreeWithDouble) {
  test::check_held_laws_agree_with_double<Q23_40>(100.0, 1e-6);
}

// Beyond the checked input range the step saturates, and says so: counted per step, outputs
// clipped (never wrapped round to the other sign).
TEST(FixedPointOscillator, SaturationDuringARunIsFlaggedNeverSilent) {
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact, 1e-3);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  Oscillator<Fixed, CoulombStickSlip> seat;
  CHECK(seat.configure(p).ok());
  seat.reset(Fixed(0), Fixed(0), Fixed(0));
  for (int n = 0; n < 100; ++n) seat.step(Fixed(0.1));
  LONGS_EQUAL(0, seat.saturated_steps());
  // 2e5 m/s^2 is far beyond input_range_m_per_s2 = 50: m a_u = 1.8e7 N does not fit.
  const auto out = seat.step(Fixed(2e5));
  CHECK_TRUE(seat.saturated());
  CHECK(seat.saturated_steps() >= 1);
  // Pushed hard in +a_u, the seat lags: a_x > 0 is clipped, not wrapped to a negative value.
  CHECK(out.a_x_m_per_s2 > Fixed(0));
  const std::uint64_t after_one = seat.saturated_steps();
  // Kept up, it drives x_r to ~1e5 m within 2 s: k x_r no longer fits either.
  for (int n = 0; n < 2000; ++n) {
    const auto later = seat.step(Fixed(2e5));
    CHECK(later.x_r_m <= Fixed(0));  // the seat lags the floor: never wrapped to the other sign
  }
  CHECK(seat.saturated_steps() > after_one);
  CHECK(seat.x_r() < Fixed(0));
  seat.reset(Fixed(0), Fixed(0), Fixed(0));
  LONGS_EQUAL(0, seat.saturated_steps());
}

TEST(FixedPointOscillator, ConfigureRefusesWhatWouldNotFitNamingTheQuantity) {
  struct Case {
    void (*change)(OscillatorParams&);
    const char* parameter;
    const char* quantity;
  };
  const Case cases[] = {
      {[](OscillatorParams& p) { p.stiffness_n_per_m = 5e6; }, "stiffness_n_per_m:", "stiffness"},
      {[](OscillatorParams& p) { p.dt_s = 2e-5; }, "dt_s:", "precision of the fixed-point scalar"},
      {[](OscillatorParams& p) { p.input_range_m_per_s2 = 1e5; },
       "input_range_m_per_s2:", "input force m*a_u"},
      {[](OscillatorParams& p) { p.displacement_range_m = 300.0; },
       "displacement_range_m:", "spring force"},
      {[](OscillatorParams& p) { p.input_range_m_per_s2 = -1.0; }, "input_range_m_per_s2:", "> 0"},
      {[](OscillatorParams& p) { p.model = FrictionModel::stribeck; }, "model:", "exp"},
      {[](OscillatorParams& p) { p.integrator = Integrator::rk4; }, "integrator:", "rk4"},
  };
  for (const Case& c : cases) {
    OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact, 1e-3);
    p.kinetic_friction_n = p.static_friction_n = 45.0;
    c.change(p);
    ConfigResult result;
    if (p.model == FrictionModel::stribeck) {
      // (An Oscillator<Fixed, StribeckStickSlip> does not compile: no exp.)
      DiscreteModel model;
      CHECK(discretise(p, model).ok());
      result = check_fixed_point_scene(p, model, Fixed::kIntegerBits, Fixed::kFractionBits,
                                       ScalarTraits<Fixed>::kEventTickLevel, ParameterUnits::si);
    } else {
      Oscillator<Fixed, CoulombStickSlip> seat;
      result = seat.configure(p);
    }
    test::check_refused_naming(result, c.parameter, c.quantity);
  }
  // The float oscillator ignores the fixed-point ranges.
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact, 1e-3);
  p.input_range_m_per_s2 = -1.0;
  Oscillator<double, CoulombStickSlip> seat;
  CHECK(seat.configure(p).ok());
}

// The extremes of the grid (test::for_each_extreme_scene) with the default ranges: refused by
// name, or run without saturation and bounded (the fixed-point form of "no NaN-equivalent
// garbage").
TEST(FixedPointOscillator, ExtremesAreRefusedByNameOrRunWithoutSaturation) {
  test::check_extremes_are_refused_by_name_or_run_without_saturation<Q23_40>(50.0);
}
