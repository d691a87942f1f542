// The Q7.24 scalar of the Cortex-M0+ build (core/fixed_point32.hpp) and the oscillator in scene
// units (models/scaled_oscillator.hpp): every operation against exact integer references with its
// saturation flagged, the event proportion without a division, the count conversions, the
// oscillator against double, configure() refusing by name, and the extreme scenes.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "fixed_point_checks.hpp"
#include "oracles.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/integrators/cubic_segment.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_oscillator.hpp"

using namespace stickslip;

namespace {

constexpr std::int32_t kMax32 = INT32_MAX;

// round(a b / 2^24), ties away from zero, in int64 (exact: |a b| < 2^62).
std::int64_t reference_product(std::int32_t a, std::int32_t b) {
  return test::rounded_product<24>(std::int64_t{a}, std::int64_t{b});
}

// A deterministic 32-bit generator (xorshift), spread over every magnitude.
struct Bits {
  std::uint64_t state = 0x9e3779b97f4a7c15u;
  std::uint32_t next() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<std::uint32_t>(state >> 11);
  }
  // A raw value in the symmetric range with a random number of significant bits.
  std::int32_t raw() {
    const int bits = static_cast<int>(next() % 31u) + 1;
    const auto magnitude = static_cast<std::int32_t>(next() >> (32 - bits));
    return (next() & 1u) ? -magnitude : magnitude;
  }
};

// The M0+ firmware's ranges: the int16 mm/s^2 input and the seat's stroke.
OscillatorParams firmware_params(FrictionModel model, Integrator integrator) {
  OscillatorParams p = test::reference_params(model, integrator, 1e-3);
  p.input_range_m_per_s2 = 32.768;
  p.displacement_range_m = 0.1;
  return p;
}

// Q7.24 runs ScaledOscillator in scene units; its conversions take SI values in and out
// (fixed_point_checks.hpp).
struct Q7_24 {
  using Scalar = Fixed32;
  template <typename Law>
  using Seat = ScaledOscillator<Fixed32, Law>;
  static constexpr const char* kName = "fixed32";
  static OscillatorParams params(FrictionModel model, Integrator integrator) {
    return firmware_params(model, integrator);
  }
  template <typename S>
  static auto& model(S& seat) {
    return seat.oscillator();
  }
  template <typename S>
  static Fixed32 input(S& seat, double a_m_per_s2) {
    return seat.acceleration(a_m_per_s2);
  }
  template <typename S>
  static double metres(S& seat, Fixed32 x_r) {
    return seat.to_si_displacement(x_r);
  }
  template <typename S>
  static double acceleration(S& seat, Fixed32 a_x) {
    return seat.to_si_acceleration(a_x);
  }
};

}  // namespace

TEST_GROUP(FixedPoint32Arithmetic){void setup() override{(void)take_fixed_point_saturation();
}
}
;

TEST(FixedPoint32Arithmetic, ProductEqualsTheRoundedExactProduct) {
  Bits bits;
  int saturated = 0;
  for (int i = 0; i < 200000; ++i) {
    const std::int32_t a = bits.raw(), b = bits.raw();
    const std::int64_t exact = reference_product(a, b);
    const Fixed32 got = Fixed32::from_raw(a) * Fixed32::from_raw(b);
    const bool fits = exact <= kMax32 && exact >= -kMax32;
    const bool flagged = take_fixed_point_saturation();
    if (fits) {
      if (got.raw() != exact || flagged) {
        FAIL(StringFromFormat("%d * %d: got %d, exact %lld, flag %d", a, b, got.raw(),
                              static_cast<long long>(exact), flagged ? 1 : 0)
                 .asCharString());
      }
    } else {
      ++saturated;
      CHECK_TRUE(flagged);
      LONGS_EQUAL(exact > 0 ? kMax32 : -kMax32, got.raw());  // clipped, never wrapped
    }
  }
  CHECK(saturated > 1000);  // the draw did reach the saturating products
  // Ties round away from zero, symmetric in sign: 1.5 ulp and -1.5 ulp.
  const Fixed32 half(0.5);
  LONGS_EQUAL(2, (Fixed32::from_raw(3) * half).raw());
  LONGS_EQUAL(-2, (Fixed32::from_raw(-3) * half).raw());
}

namespace {

// round(a b / 2^F) of magnitudes from ARMv6-M's half-word products against the 64-bit product
// (uint64 holds a b < 2^62 exactly): equal wherever the quotient fits, above kMax32 where not.
template <int F>
int half_word_product_mismatches(Bits& bits, int draws, int& too_large) {
  const std::uint32_t edges[] = {0u,
                                 1u,
                                 0xffffu,
                                 0x10000u,
                                 0x7fffffffu,
                                 0x7fff0000u,
                                 0x0000ffffu,
                                 1u << 30,
                                 (1u << (F - 1)) - 1u,
                                 1u << (F - 1),
                                 0x00ff00ffu};
  int mismatches = 0;
  const auto check = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t exact = (std::uint64_t{a} * b + (std::uint64_t{1} << (F - 1))) >> F;
    const std::uint32_t got = fixed_point_detail::round_shift_product_halves<F>(a, b);
    if (exact > static_cast<std::uint64_t>(kMax32)) {
      ++too_large;
      if (got <= static_cast<std::uint32_t>(kMax32)) ++mismatches;
    } else if (got != exact) {
      ++mismatches;
    }
  };
  for (const std::uint32_t a : edges)
    for (const std::uint32_t b : edges) check(a, b);
  for (int i = 0; i < draws; ++i) {
    const auto magnitude = [&bits] {
      const std::int32_t raw = bits.raw();
      return static_cast<std::uint32_t>(raw < 0 ? -raw : raw);
    };
    check(magnitude(), magnitude());
  }
  return mismatches;
}

}  // namespace

TEST(FixedPoint32Arithmetic, HalfWordProductEqualsTheRoundedExactProduct) {
  Bits bits;
  int too_large = 0;
  LONGS_EQUAL(0, half_word_product_mismatches<17>(bits, 100000, too_large));
  LONGS_EQUAL(0, half_word_product_mismatches<24>(bits, 200000, too_large));
  LONGS_EQUAL(0, half_word_product_mismatches<29>(bits, 100000, too_large));
  CHECK(too_large > 1000);  // the draw did reach quotients that do not fit
}

// The event search's halves and quarters: the same bits as the product by 2^-shift, in both
// fixed-point formats (Q23.40's raw values from the same draw, spread over its wider range).
TEST(FixedPoint32Arithmetic, DivisionByAPowerOfTwoIsTheProductsRounding) {
  Bits bits;
  int mismatches = 0;
  for (int i = 0; i < 100000; ++i) {
    const std::int32_t raw = bits.raw();
    const auto wide = static_cast<std::int64_t>(raw) * (std::int64_t{1} << (i % 24));
    for (const int shift : {1, 2, 5, 23}) {
      const Fixed32 v = Fixed32::from_raw(raw);
      const Fixed32 product = v * Fixed32(std::ldexp(1.0, -shift));
      if (ScalarTraits<Fixed32>::divide_by_power_of_two(v, shift) != product) ++mismatches;
      const Fixed w = Fixed::from_raw(wide);
      const Fixed wide_product = w * Fixed(std::ldexp(1.0, -shift));
      if (ScalarTraits<Fixed>::divide_by_power_of_two(w, shift) != wide_product) ++mismatches;
    }
  }
  LONGS_EQUAL(0, mismatches);
  LONGS_EQUAL(1, ScalarTraits<Fixed32>::divide_by_power_of_two(Fixed32::from_raw(1), 1).raw());
  LONGS_EQUAL(-1, ScalarTraits<Fixed32>::divide_by_power_of_two(Fixed32::from_raw(-1), 1).raw());
  LONGS_EQUAL(0, ScalarTraits<Fixed32>::divide_by_power_of_two(Fixed32::from_raw(1), 2).raw());
  CHECK_FALSE(take_fixed_point_saturation());
}

// What the Q7.24 step skips in scene units (models/oscillator.hpp, kSceneUnits): a product by
// m = 1 or dt = 1, by a direction of +-1, and the input's interpolation at the step's start are
// the operand itself, its negation and a0, bit for bit, over the whole format.
TEST(FixedPoint32Arithmetic, ProductsByOneAndTheInputAtTheStartAreTheOperandsThemselves) {
  Bits bits;
  int mismatches = 0;
  const Fixed32 one(1.0), minus_one(-1.0);
  for (int i = 0; i < 200000; ++i) {
    const Fixed32 v =
        Fixed32::from_raw(i < 4 ? (i < 2 ? kMax32 - i : -kMax32 + i - 2) : bits.raw());
    const Fixed32 w = Fixed32::from_raw(bits.raw());
    if (v * one != v || one * v != v || v * minus_one != -v) ++mismatches;
    if ((StepInput<Fixed32>{v, w}.at(Fixed32(0.0)) != v)) ++mismatches;
  }
  LONGS_EQUAL(0, mismatches);
  CHECK_FALSE(take_fixed_point_saturation());
}

TEST(FixedPoint32Arithmetic, EveryOverflowSaturatesAndSetsTheStickyFlag) {
  const Fixed32 big = Fixed32::from_raw(kMax32 - 5);
  CHECK_FALSE(fixed_point_saturated());
  LONGS_EQUAL(kMax32, (big + Fixed32::from_raw(6)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax32, (-big - Fixed32::from_raw(6)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  // The symmetric range: -2^31 is never produced, so negation cannot overflow.
  LONGS_EQUAL(-kMax32, (Fixed32::from_raw(-kMax32) - Fixed32::from_raw(1)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax32, (-big - Fixed32::from_raw(5)).raw());  // exactly the end: no flag
  CHECK_FALSE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax32, Fixed32::from_raw(INT32_MIN).raw());
  LONGS_EQUAL(kMax32, Fixed32(1e9).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(-kMax32, Fixed32(-200).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(kMax32, Fixed32(128.0).raw());  // one ulp beyond the largest value
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(0, Fixed32(std::nan("")).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(kMax32, (Fixed32(1) / Fixed32(0)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  LONGS_EQUAL(kMax32, (Fixed32(100) / Fixed32(0.5)).raw());
  CHECK_TRUE(take_fixed_point_saturation());
  // In range: no flag.
  DOUBLES_EQUAL(127.5, (Fixed32(127) + Fixed32(0.5)).to_double(), 0.0);
  DOUBLES_EQUAL(-3.0, (Fixed32(1.5) * Fixed32(-2)).to_double(), 0.0);
  DOUBLES_EQUAL(0.25, (Fixed32(1) / Fixed32(4)).to_double(), 0.0);
  CHECK_FALSE(take_fixed_point_saturation());
}

TEST(FixedPoint32Arithmetic, ConversionsRoundToNearestTiesAwayFromZero) {
  LONGS_EQUAL(1, Fixed32(0.5 / Fixed32::kScale).raw());
  LONGS_EQUAL(-1, Fixed32(-0.5 / Fixed32::kScale).raw());
  LONGS_EQUAL(0, Fixed32(0.49 / Fixed32::kScale).raw());
  LONGS_EQUAL(3 << 24, Fixed32(3).raw());
  LONGS_EQUAL(5u, static_cast<unsigned>(Fixed32(5.99)));
  CHECK_FALSE(take_fixed_point_saturation());
}

// The event instants n/d in [0, 1] by shift-and-subtract, no division: exactly round(n/d 2^F)
// (ties up) against integer division, for both fixed-point formats.
TEST(FixedPoint32Arithmetic, ProportionIsTheRoundedQuotientWithoutADivision) {
  Bits bits;
  for (int i = 0; i < 100000; ++i) {
    std::int32_t n = bits.raw(), d = bits.raw();
    if (d == 0) continue;
    const Fixed32 got =
        ScalarTraits<Fixed32>::proportion(Fixed32::from_raw(n), Fixed32::from_raw(d));
    std::int64_t expected = 0;
    if (n != 0 && (n < 0) == (d < 0)) {
      const std::int64_t un = n < 0 ? -std::int64_t{n} : n, ud = d < 0 ? -std::int64_t{d} : d;
      expected = un >= ud ? (std::int64_t{1} << 24) : ((un << 25) / ud + 1) / 2;
    }
    if (got.raw() != expected) {
      FAIL(StringFromFormat("proportion(%d, %d) = %d, expected %lld", n, d, got.raw(),
                            static_cast<long long>(expected))
               .asCharString());
    }
  }
  // Q23.40: against the 128-bit quotient.
  __extension__ typedef unsigned __int128 U128;
  for (int i = 0; i < 20000; ++i) {
    const std::int64_t d = static_cast<std::int64_t>(bits.next()) << 31 | bits.next() | 1;
    const std::int64_t n = static_cast<std::int64_t>((static_cast<U128>(d) * bits.next()) >> 32);
    const Fixed got = ScalarTraits<Fixed>::proportion(Fixed::from_raw(-n), Fixed::from_raw(-d));
    const U128 expected = ((static_cast<U128>(n) << 41) / static_cast<U128>(d) + 1) / 2;
    CHECK_EQUAL(static_cast<std::int64_t>(expected), got.raw());
  }
  CHECK_FALSE(take_fixed_point_saturation());
}

// mm/s^2 counts to scene units and back: within half an ulp (plus the factor's 2^-25) of the
// exact product, saturation flagged, output counts clamped.
TEST(FixedPoint32Arithmetic, CountScaleConvertsWithinTheFactorsPrecision) {
  const double factor = 3.3e-7;  // scene units per count (a_u in mm/s^2 on the firmware)
  CountScale<Fixed32> in, out;
  CHECK_TRUE(in.set_count_to_scalar(factor));
  CHECK_TRUE(out.set_scalar_to_count(1.0 / factor));
  CHECK_FALSE(in.set_count_to_scalar(2.0));  // would need a left shift
  CHECK_FALSE(in.set_count_to_scalar(-1.0));
  double worst = 0.0;
  for (std::int32_t count = -32768; count <= 32767; count += 7) {
    const double exact = count * factor * Fixed32::kScale;
    const double error = std::fabs(in.to_scalar(count).raw() - exact);
    if (error > worst) worst = error;
    const std::int32_t back = out.to_count(in.to_scalar(count), 32767);
    CHECK(std::abs(back - count) <= 1);
  }
  test::note_margin("count -> Q7.24 error, ulp", worst,
                    0.5 + 32768 * factor * Fixed32::kScale * 0x1p-24);
  CHECK(worst <= 0.5 + 32768 * factor * Fixed32::kScale * 0x1p-24);
  LONGS_EQUAL(32767, out.to_count(Fixed32(100), 32767));
  LONGS_EQUAL(-32767, out.to_count(Fixed32(-100), 32767));
  CHECK_FALSE(take_fixed_point_saturation());
  CountScale<Fixed32> huge;
  CHECK_TRUE(huge.set_count_to_scalar(0.01));  // 30000 counts = 300: beyond the format
  LONGS_EQUAL(kMax32, huge.to_scalar(30000).raw());
  CHECK_TRUE(take_fixed_point_saturation());
}

// The conversion rounds the product by its stored factor (24 significant bits, 2^-shift) to
// nearest, ties away from zero, at every shift it accepts (1 to 62, both halves of a 64-bit
// word): against the exact product in 128 bits, with the factor formed as its documentation says.
TEST(FixedPoint32Arithmetic, CountScaleRoundsTheProductByItsStoredFactorToNearestAtEveryShift) {
  __extension__ typedef __int128 I128;
  test::SplitMix64 random(29);
  long checked = 0;
  for (int shift = 1; shift <= 62; ++shift) {
    for (int trial = 0; trial < 40; ++trial) {
      // scalar -> count: factor = mantissa 2^exponent with shift = 48 - exponent.
      const double mantissa = random.uniform(0.5, 1.0);
      const double factor = std::ldexp(mantissa, 48 - shift);
      CountScale<Fixed32> scale;
      CHECK_TRUE(scale.set_scalar_to_count(factor));
      const auto multiplier = static_cast<std::int64_t>(std::ldexp(mantissa, 24) + 0.5);
      for (int sample = 0; sample < 50; ++sample) {
        // Raw values of every size, small ones often (ties and the rounding carry).
        const int bits = static_cast<int>(random.uniform(0.0, 31.0));
        auto raw = static_cast<std::int32_t>(random.uniform(-1.0, 1.0) * std::ldexp(1.0, bits));
        if (sample == 0) raw = kMax32;
        if (sample == 1) raw = -kMax32;
        const I128 product = static_cast<I128>(raw < 0 ? -std::int64_t{raw} : raw) * multiplier;
        const I128 rounded = (product + (static_cast<I128>(1) << (shift - 1))) >> shift;
        const I128 clamped = rounded > INT32_MAX ? INT32_MAX : rounded;
        const auto expected = static_cast<std::int32_t>(raw < 0 ? -clamped : clamped);
        const std::int32_t got = scale.to_count(Fixed32::from_raw(raw), INT32_MAX);
        CHECK_TEXT(got == expected, StringFromFormat("shift %d raw %ld: %ld, expected %ld", shift,
                                                     static_cast<long>(raw), static_cast<long>(got),
                                                     static_cast<long>(expected))
                                        .asCharString());
        ++checked;
      }
    }
  }
  CHECK(checked == 62 * 40 * 50);
}

TEST_GROUP(ScaledFixedPoint32Oscillator){void setup() override{(void)take_fixed_point_saturation();
}
}
;

// With the firmware's ranges.
TEST(ScaledFixedPoint32Oscillator, StickSlipAgreesWithDoubleOnTheLorryScene) {
  test::check_stick_slip_agrees_with_double_on_the_lorry_scene<Q7_24>();
}

// c v_r must fit the format at the declared ranges (4 m/s here): c = 5 s/m gives 20 <= 32.
TEST(ScaledFixedPoint32Oscillator, HeldLawsAgreeWithDouble) {
  test::check_held_laws_agree_with_double<Q7_24>(5.0, 1e-5);
}

// The hardest input for the event search (port/baremetal/src/hardest_input.cpp's, which QEMU
// runs): a_u chosen from the seat's own state so that the limit force -(m a_u + k x_r) lands on
// +F_fs or -F_fs (alternating every 7 steps) plus an offset of random size (down to 1e-3 m/s^2)
// and sign, with every fourth 1000 steps full-range jumps, in whole words of SeatInput.a_u
// (2^-10 m/s^2; finer offsets fall below Q7.24's resolution of the force, 2e-4 m/s^2 in a_u, and
// would only compare roundings). `step(a_u_m_per_s2)` steps the seats under test; `x_r_m()` reads
// the double seat's state.
template <typename Step, typename Position>
void drive_at_the_break_away_threshold(const OscillatorParams& p, int steps, Step step,
                                       Position x_r_m) {
  Bits bits;
  const auto uniform = [&bits] { return static_cast<double>(bits.next()) / 2147483648.0 - 1.0; };
  for (int n = 0; n < steps; ++n) {
    double a_u = 30.0 * uniform();
    if ((n / 1000) % 4 != 0) {
      const double side = (n / 7) % 2 == 0 ? 1.0 : -1.0;
      a_u = -(side * p.static_friction_n + p.stiffness_n_per_m * x_r_m()) / p.mass_kg +
            uniform() * std::pow(10.0, -3.0 * std::fabs(uniform()));
    }
    step(std::round(a_u * 1024.0) / 1024.0);
  }
}

// The Q7.24 step locates events on the cubic polynomial of one whole step, not on a grid. Held at
// the break-away threshold, where every step may stick, break away or reverse, the stuck fraction
// stays within 1e-3 of double's and T_ax within 5e-4 (measured 4.5e-4 and 1.8e-4; the bisection
// on ticks of dt/16 with linear interpolation that this replaced was 5.8e-3 off in p here). Not
// tighter: offsets down to 1e-3 m/s^2 are 5 units of the format's force resolution, so a few
// decisions at the threshold are the format's rounding. No step runs out of events, and none
// locates more than the exact solution does.
TEST(ScaledFixedPoint32Oscillator, AtTheBreakAwayThresholdFollowsDouble) {
  using Seat = Oscillator<Fixed32, CoulombStickSlip>;
  OscillatorParams p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  p.kinetic_friction_n = p.static_friction_n = 45.0;  // the firmware's seat
  ScaledOscillator<Fixed32, CoulombStickSlip> seat;
  Oscillator<double, CoulombStickSlip> exact;
  CHECK(seat.configure(p).ok());
  CHECK(exact.configure(p).ok());
  double stuck = 0.0, stuck_exact = 0.0, a_x_sq = 0.0, a_x_sq_exact = 0.0;
  int most_events = 0, most_events_exact = 0;
  constexpr int kSteps = 60000;
  drive_at_the_break_away_threshold(
      p, kSteps,
      [&](double a_u) {
        const auto out = seat.step(seat.acceleration(a_u));
        const auto out_exact = exact.step(a_u);
        stuck += ScalarTraits<Fixed32>::to_double(out.stuck_fraction);
        stuck_exact += out_exact.stuck_fraction;
        const double a_x = seat.to_si_acceleration(out.a_x_m_per_s2);
        a_x_sq += a_x * a_x;
        a_x_sq_exact += out_exact.a_x_m_per_s2 * out_exact.a_x_m_per_s2;
        most_events = out.events > most_events ? out.events : most_events;
        most_events_exact =
            out_exact.events > most_events_exact ? out_exact.events : most_events_exact;
      },
      [&] { return exact.x_r(); });
  test::note_margin("p against double", std::fabs(stuck - stuck_exact) / kSteps, 1e-3);
  test::note_margin("T_ax against double", std::fabs(std::sqrt(a_x_sq / a_x_sq_exact) - 1.0), 5e-4);
  DOUBLES_EQUAL(stuck_exact / kSteps, stuck / kSteps, 1e-3);
  DOUBLES_EQUAL(1.0, std::sqrt(a_x_sq / a_x_sq_exact), 5e-4);
  CHECK(stuck_exact / kSteps > 0.2);  // the input does hold the seat at the threshold
  LONGS_EQUAL(0, seat.oscillator().event_budget_exhausted());
  LONGS_EQUAL(0, seat.oscillator().saturated_steps());
  test::note_margin("most events in a step, fixed32", most_events, Seat::kEventBudget);
  test::note_margin("most events in a step, double", most_events_exact, Seat::kEventBudget);
  // The budget is reached (and never cut a step short, above); no step of the exact solution,
  // whose budget is 32, needs more than the 3 events step_common.hpp derives.
  LONGS_EQUAL(Seat::kEventBudget, most_events);
  CHECK(most_events_exact <= kMaxEventsOfTheExactSolutionPerStep);
  CHECK(most_events <= most_events_exact);
}

// The cubic segment of one step in scene units against the exact solution of a damped free
// oscillation (x_r = A e^(-zeta w t) cos(w_d t)), whose n-th derivative is at most A w^n: position
// and velocity within the Taylor remainders A w^5/120 (x_r, degree 4) and A w^5/24 (v_r, degree 3)
// plus a few units of the last place over the whole step, and the crossing of v_r = 0 inside the
// step at the exact instant to within the velocity's error over the slope there.
TEST(ScaledFixedPoint32Oscillator, CubicSegmentIsTheExactSolutionToTheFormatsResolution) {
  // Scene units: dt = 1, the reference seat's w dt = 0.0114 and zeta = 0.25; an oscillation fast
  // enough (w = 0.3 per step) to put a turning point inside one step, so that the test sees a dip.
  const double w = 0.3, zeta = 0.25, wd = w * std::sqrt(1.0 - zeta * zeta);
  const double k_over_m = w * w, b_over_m = 2.0 * zeta * w;
  const auto x_at = [&](double t) { return 0.5 * std::exp(-zeta * w * t) * std::cos(wd * t); };
  const auto v_at = [&](double t) {
    return 0.5 * std::exp(-zeta * w * t) * (-zeta * w * std::cos(wd * t) - wd * std::sin(wd * t));
  };
  const double eps = ScalarTraits<Fixed32>::to_double(ScalarTraits<Fixed32>::epsilon());
  // Start 0.4 steps before v_r = 0 at t = (atan(-zeta w / wd) + pi) / wd.
  const double t_zero = (std::atan(-zeta * w / wd) + std::acos(-1.0)) / wd;
  const double t0 = t_zero - 0.4;
  const double x0 = x_at(t0), v0 = v_at(t0);
  const double a0 = -(k_over_m * x0 + b_over_m * v0);
  const double j0 = -(k_over_m * v0 + b_over_m * a0);
  const double s0 = -(k_over_m * a0 + b_over_m * j0);
  const auto q = [](double value) { return Fixed32(value); };
  const CubicSegment<Fixed32> segment(q(x0), q(v0), q(a0), q(j0), q(s0));
  // The remainders (at the reference seat's w dt = 0.0114 they are 1e-11 of A, below the
  // resolution; this fast oscillation makes them visible).
  const double x_remainder = 0.5 * std::pow(w, 5) / 120.0 + 8 * eps;
  const double v_remainder = 0.5 * std::pow(w, 5) / 24.0 + 8 * eps;
  for (int i = 0; i <= 8; ++i) {
    const double u = i / 8.0;
    DOUBLES_EQUAL(x_at(t0 + u), ScalarTraits<Fixed32>::to_double(segment.position(q(u))),
                  x_remainder);
    DOUBLES_EQUAL(v_at(t0 + u), ScalarTraits<Fixed32>::to_double(segment.velocity(q(u))),
                  v_remainder);
  }
  // v_r d falls through 0 at u = 0.4, d the direction of v_r at the start.
  const Fixed32 d(v0 > 0.0 ? 1.0 : -1.0);
  Fixed32 root;
  CHECK(segment.first_crossing(d, q(1.0), root));
  const double slope = k_over_m * std::fabs(x_at(t_zero));  // |dv_r/dt| where v_r = 0
  DOUBLES_EQUAL(0.4, ScalarTraits<Fixed32>::to_double(root), v_remainder / slope);
}

// The cubic search's root is exact to the format's rounding. On 200,000 random segments in scene
// units (moving, and from rest, where the search runs on v_r / u), with the snap a seat makes,
// -((k/m) a + (b/m) jerk), for the reference seat and for seats anywhere in what configure()
// accepts ((b/m) dt + (k/m) dt^2 / 2 < 1), the polynomial the segment holds, evaluated in double
// at the root found, is within (2 + |slope|) units of Q7.24's last place: |slope| for the root's
// own rounding (half a unit either side) and 2 for the rounding of the format's evaluations that
// steer it (three products and adds). And it is the first crossing: the value along d stays
// above that tolerance before the root. Two Newton steps would leave up to 73 units on the
// coarsest seats (kCubicRootNewtonSteps is 3), and regula falsi's 6 iterations thousands.
TEST(ScaledFixedPoint32Oscillator, CubicSegmentRootIsExactToTheFormatsRounding) {
  using S = ScalarTraits<Fixed32>;
  const double lsb = S::to_double(S::epsilon());
  test::SplitMix64 random(20261127u);
  const auto magnitude = [&](double lo_exponent, double hi_exponent) {
    return std::pow(10.0, random.uniform(lo_exponent, hi_exponent));
  };
  long found = 0, from_rest = 0;
  double worst = 0.0;
  for (int n = 0; n < 200000; ++n) {
    const double d = random.uniform(-1.0, 1.0) < 0.0 ? -1.0 : 1.0;
    const bool rest = n % 4 == 0;
    // (b/m) dt and (k/m) dt^2: the reference seat's at 1 ms, or any the condition admits.
    double damping = 5.7e-3, stiffness = 1.3e-4;
    if (n % 2 == 1) {
      damping = random.uniform(0.0, 1.0);
      stiffness = 2.0 * (1.0 - damping) * random.uniform(0.0, 1.0);
    }
    const double v0 = rest ? 0.0 : d * magnitude(-7.0, -1.0);
    const double a0 = rest ? d * magnitude(-7.0, -2.0) : -d * magnitude(-6.0, 0.0);
    const double jerk = (rest ? -d : random.uniform(-1.0, 1.0)) * magnitude(-6.0, 0.0);
    const Fixed32 snap(-(stiffness * a0 + damping * jerk));
    const Fixed32 hi(random.uniform(0.05, 1.0));
    const CubicSegment<Fixed32> segment(Fixed32(0.0), Fixed32(v0), Fixed32(a0), Fixed32(jerk),
                                        snap);
    Fixed32 root;
    if (!segment.first_crossing(Fixed32(d), hi, root)) continue;
    ++found;
    if (rest) ++from_rest;
    // The coefficients the segment holds, as its constructor rounds them; from rest, v_r / u.
    const double c[4] = {S::to_double(Fixed32(v0)), S::to_double(Fixed32(a0)),
                         S::to_double(S::divide_by_power_of_two(Fixed32(jerk), 1)),
                         S::to_double(snap * Fixed32(1.0 / 6.0))};
    const double* p = rest ? c + 1 : c;
    const double top = rest ? 0.0 : c[3];
    const auto along = [&](double u) { return d * (p[0] + u * (p[1] + u * (p[2] + u * top))); };
    const double u = S::to_double(root);
    CHECK(u > 0.0 && u <= S::to_double(hi));
    const double slope = std::fabs(p[1] + u * (2.0 * p[2] + 3.0 * top * u));
    const double tolerance = (2.0 + slope) * lsb;
    const double residual = std::fabs(along(u));
    worst = std::max(worst, residual / lsb);
    CHECK_TEXT(
        residual <= tolerance,
        StringFromFormat("|v(root)| = %.2f units at u = %.9f, slope %.3g", residual / lsb, u, slope)
            .asCharString());
    for (int i = 1; i < 64; ++i) CHECK(along(u * i / 64.0) >= -tolerance);
  }
  test::note_margin("cubic root's residual, units of the last place", worst, 2.0);
  CHECK(found > 50000);
  CHECK(from_rest > 10000);
}

// From rest, a slip that starts with a_r d > 0 does not cross 0 at its start, however small a_r is
// against the format's resolution (v_r itself is below it there): the search runs on v_r / u.
TEST(ScaledFixedPoint32Oscillator, CubicSegmentFromRestDoesNotCrossAtItsStart) {
  using S = ScalarTraits<Fixed32>;
  const Fixed32 a0 = Fixed32::from_raw(3);  // 1.8e-7: v_r(2^-16) is 3e-12, 0 in the format
  const Fixed32 jerk(-4e-4);                // turns v_r back: it crosses 0 at u = 2 a0 / |jerk|
  const CubicSegment<Fixed32> segment(Fixed32(0.01), Fixed32(0.0), a0, jerk, Fixed32(0.0));
  Fixed32 root;
  CHECK(segment.first_crossing(Fixed32(1.0), Fixed32(1.0), root));
  // v_r / u = a0 + (jerk / 2) u is linear: the root to the rounding of jerk / 2 (half a unit of
  // the last place in 3355 of them).
  const double expected = 2.0 * S::to_double(a0) / -S::to_double(jerk);
  DOUBLES_EQUAL(expected, S::to_double(root), 2e-4 * expected);
  // Rising throughout: no crossing at all.
  const CubicSegment<Fixed32> rising(Fixed32(0.01), Fixed32(0.0), a0, -jerk, Fixed32(0.0));
  CHECK_FALSE(rising.first_crossing(Fixed32(1.0), Fixed32(1.0), root));
}

// Beyond the declared input range the step saturates and says so: counted per step, outputs
// clipped (never wrapped round to the other sign).
TEST(ScaledFixedPoint32Oscillator, SaturationDuringARunIsFlaggedNeverSilent) {
  OscillatorParams p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  ScaledOscillator<Fixed32, CoulombStickSlip> seat;
  CHECK(seat.configure(p).ok());
  auto& model = seat.oscillator();
  model.reset(Fixed32(0), Fixed32(0), Fixed32(0));
  for (int n = 0; n < 100; ++n) seat.step(seat.acceleration(0.1));
  LONGS_EQUAL(0, model.saturated_steps());
  // 5e5 m/s^2 is far beyond the declared 32.768: the input itself does not fit the format. The
  // conversion sets the flag, and the step it feeds counts it with its own.
  const Fixed32 too_big = seat.acceleration(5e5);
  CHECK_TRUE(take_fixed_point_saturation());
  const auto out = seat.step(seat.acceleration(5e5));
  CHECK_TRUE(model.saturated());
  CHECK(model.saturated_steps() >= 1);
  CHECK(out.a_x_m_per_s2 > Fixed32(0));  // pushed in +a_u, the seat lags: clipped, not wrapped
  const std::uint64_t after_one = model.saturated_steps();
  for (int n = 0; n < 2000; ++n) {
    const auto later = seat.step(too_big);
    CHECK(later.x_r_m <= Fixed32(0));  // never wrapped to the other sign
  }
  CHECK(model.saturated_steps() > after_one);
  model.reset(Fixed32(0), Fixed32(0), Fixed32(0));
  LONGS_EQUAL(0, model.saturated_steps());
}

TEST(ScaledFixedPoint32Oscillator, ConfigureRefusesWhatWouldNotFitNamingTheQuantity) {
  struct Case {
    void (*change)(OscillatorParams&);
    const char* parameter;
    const char* quantity;
  };
  const Case cases[] = {
      // A 10 m stroke makes L = 0.3 m: 45 N of friction is then below the resolution.
      {[](OscillatorParams& p) { p.displacement_range_m = 10.0; }, "kinetic_friction_n:", "F_fk"},
      // dt = 0.2 ms: k dt^2/m = 5.2e-6 has too few significant bits (dt >= 0.69 ms holds 11).
      {[](OscillatorParams& p) { p.dt_s = 2e-4; }, "stiffness_n_per_m:", "k/m"},
      // dt = 10 us: k dt^2/m = 1.3e-8 is below what the core accepts at all.
      {[](OscillatorParams& p) { p.dt_s = 1e-5; }, "stiffness_n_per_m:", "in scene units"},
      // dt = 0.1 s: (b/m) dt + (k/m) dt^2/2 = 1.2, where a step could hold more events than
      // the budget of 3 (step_common.hpp).
      {[](OscillatorParams& p) { p.dt_s = 0.1; }, "dt_s:", "(b/m) dt + (k/m) dt^2/2"},
      {[](OscillatorParams& p) { p.integrator = Integrator::rk4; }, "integrator:", "rk4"},
      {[](OscillatorParams& p) { p.input_range_m_per_s2 = -1.0; }, "input_range_m_per_s2:", "> 0"},
      {[](OscillatorParams& p) { p.mass_kg = -1.0; }, "mass_kg:", "must be"},
  };
  for (const Case& c : cases) {
    OscillatorParams p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
    p.kinetic_friction_n = p.static_friction_n = 45.0;
    c.change(p);
    ScaledOscillator<Fixed32, CoulombStickSlip> seat;
    const ConfigResult result = seat.configure(p);
    test::check_refused_naming(result, c.parameter, c.quantity);
  }
  // The scaled refusals say in which units their values are.
  OscillatorParams p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  p.displacement_range_m = 10.0;
  ScaledOscillator<Fixed32, CoulombStickSlip> seat;
  const ConfigResult result = seat.configure(p);
  CHECK_TEXT(test::contains(result.message.c_str(), "in scene units"), result.message.c_str());
  CHECK_TEXT(test::contains(result.message.c_str(), "displacement_range_m"),
             result.message.c_str());
  // The oscillator itself runs Q7.24 in scene units only, where dt = 1: the firmware's scene
  // in them is accepted, the same scene with any other step is refused by name.
  OscillatorParams firmware = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  firmware.kinetic_friction_n = firmware.static_friction_n = 45.0;
  ScaledOscillator<Fixed32, CoulombStickSlip> scaled;
  CHECK(scaled.configure(firmware).ok());
  OscillatorParams scene = to_scene_units(firmware, scaled.units());
  Oscillator<Fixed32, CoulombStickSlip> direct;
  CHECK_TEXT(direct.configure(scene).ok(), direct.configure(scene).message.c_str());
  scene.dt_s = 0.999;
  test::check_refused_naming(direct.configure(scene), "dt_s:", "scene units");
  scene.dt_s = 1.0;
  scene.mass_kg = 1.001;
  test::check_refused_naming(direct.configure(scene), "mass_kg:", "scene units");
}

// A refusal in scene units states its value in them, with their units (time dt, mass m, length
// L), and whole: the SI unit beside a value in scene units would misstate it by orders of
// magnitude (k/m of the reference seat is 130 1/s^2 but 5.2e-6 1/dt^2 at dt = 0.2 ms).
TEST(ScaledFixedPoint32Oscillator, RefusalsStateTheirValuesInSceneUnitsAndWhole) {
  const auto ends_with_the_limit = [](const ConfigResult& result) {
    const char* text = result.message.c_str();
    const std::size_t length = std::strlen(text);
    CHECK_TEXT(length > 0 && text[length - 1] == ')', text);
  };
  char expected[96];
  // dt = 0.2 ms: k/m in scene units is k dt^2 / m.
  OscillatorParams p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  p.dt_s = 2e-4;
  ScaledOscillator<Fixed32, CoulombStickSlip> seat;
  ConfigResult result = seat.configure(p);
  std::snprintf(expected, sizeof expected, "k/m = %g 1/dt^2 is below",
                p.stiffness_n_per_m * p.dt_s * p.dt_s / p.mass_kg);
  CHECK_TEXT(test::contains(result.message.c_str(), expected), result.message.c_str());
  ends_with_the_limit(result);
  // A 10 m stroke: F_fk in scene units is F_fk dt^2 / (m L).
  p = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  p.displacement_range_m = 10.0;
  result = seat.configure(p);
  const double length_m = seat.units().length_m;  // chosen before the refusal
  std::snprintf(expected, sizeof expected, "F_fk = %g m L/dt^2 is below",
                p.kinetic_friction_n * p.dt_s * p.dt_s / (p.mass_kg * length_m));
  CHECK_TEXT(test::contains(result.message.c_str(), expected), result.message.c_str());
  ends_with_the_limit(result);
  // In SI (Q23.40) the same check keeps SI units.
  OscillatorParams si = firmware_params(FrictionModel::stick_slip, Integrator::exact);
  si.stiffness_n_per_m = 5e6;
  Oscillator<Fixed, CoulombStickSlip> q23;
  result = q23.configure(si);
  CHECK_TEXT(test::contains(result.message.c_str(), "the stiffness k = 5e+06 N/m does not fit"),
             result.message.c_str());
  ends_with_the_limit(result);
}

// The extremes of the grid (test::for_each_extreme_scene) with the firmware's input range and a
// 1 m stroke.
TEST(ScaledFixedPoint32Oscillator, ExtremesAreRefusedByNameOrRunWithoutSaturation) {
  test::check_extremes_are_refused_by_name_or_run_without_saturation<Q7_24>(32.768);
}
