// A saturating Q7.24 fixed-point scalar on int32 with int64 intermediates, for cores with only a
// 32-bit multiply and few registers (Cortex-M0/M0+). The oscillator, the friction laws and the
// integrators run with it from the same source as with float, double and Q23.40.
//
// Why a second format: Q23.40 (core/fixed_point.hpp) holds the scene in SI units, which span 13
// decades, and costs a 64 x 64-bit product per multiply; on ARMv6-M that is ~70 instructions and a
// stack frame full of 64-bit temporaries. A 32-bit word cannot hold SI units, but it can hold the
// scene in scaled units in which every quantity the step forms is O(1): time in steps (dt = 1),
// mass in seat masses (m = 1) and length in a unit L that configure() chooses from the declared
// ranges (models/scaled_oscillator.hpp). The template source does not know about the scaling: it
// is applied to the parameters before configure() and to the input and outputs at the boundary.
//
// @par Scaling and overflow (a, b in Q7.24, raw values r_a, r_b in int32)
// - Range: the raw value is kept in [-(2^31 - 1), 2^31 - 1] (+-128 - 2^-24), symmetric; any result
//   outside saturates to the nearest end and sets the same sticky flag as Q23.40
//   (fixed_point_saturated()): never a silent wrap-around.
// - a + b, a - b: exact; saturate on overflow.
// - a * b: the exact 62-bit product of the magnitudes (four 16 x 16 -> 32-bit products on ARMv6-M,
//   no library call), rounded to Q7.24 to nearest, ties away from zero (symmetric); saturates.
// - a / b: (r_a 2^24) / r_b in int64, truncated toward zero; b == 0 saturates and flags. Only the
//   rational friction law divides; the stick-slip step does not (ScalarTraits::proportion()).
// - proportion(n, d) for 0 <= n <= d: n/d in [0, 1] by 24 rounds of shift-and-subtract, rounded to
//   nearest (ties up): the in-step event instants, without a divide routine.
// - Conversions: from double rounds to nearest (ties away from zero); from int/unsigned is exact;
//   both saturate and flag out of range. Conversion to unsigned truncates toward zero.
#pragma once

#include <climits>
#include <cstdint>

#include "stickslip/core/fixed_point.hpp"

namespace stickslip {

namespace fixed_point_detail {

constexpr std::int32_t kMaxRaw32 = INT32_MAX;

STICKSLIP_FIXED_INLINE constexpr std::int32_t saturate32(std::int64_t value) noexcept {
  if (value > kMaxRaw32) {
    flag_saturation();
    return kMaxRaw32;
  }
  if (value < -kMaxRaw32) {
    flag_saturation();
    return -kMaxRaw32;
  }
  return static_cast<std::int32_t>(value);
}

// In 32-bit words: on ARMv6-M a sign-extended 64-bit sum and its two-word range check cost about
// 17 instructions a call, this about 11. The only sum that does not overflow int32 and still
// leaves the symmetric range is -2^31, reached from two negative operands.
STICKSLIP_FIXED_INLINE constexpr std::int32_t add_raw32_portable(std::int32_t a,
                                                                 std::int32_t b) noexcept {
  std::int32_t sum = 0;
  if (__builtin_add_overflow(a, b, &sum) || sum == INT32_MIN) {
    flag_saturation();
    return a < 0 ? -kMaxRaw32 : kMaxRaw32;
  }
  return sum;
}

#ifdef STICKSLIP_THUMB1_ASSEMBLY
// The same sum by the flags: the overflow is the V flag of ADDS, which C++ cannot read (GCC tests
// it with three logical operations, and -2^31 with a constant it builds in a register). The sum
// leaves the symmetric range exactly where ADDS overflows or where SUBS of 1 from the sum does
// (the sum is -2^31): about 7 instructions a call. Checked against 64-bit sums on the target
// (port/baremetal/src/kernel_check.cpp, CTest embedded.kernels_match_reference_code).
STICKSLIP_FIXED_INLINE std::int32_t add_raw32_by_flags(std::int32_t a, std::int32_t b) noexcept {
  std::int32_t sum = 0, below = 0;
  asm goto(STICKSLIP_THUMB1_UNIFIED_BEGIN
           "adds %0, %2, %3\n\t"
           "bvs %l[out_of_range]\n\t"
           "subs %1, %0, #1\n\t"
           "bvs %l[out_of_range]" STICKSLIP_THUMB1_UNIFIED_END
           : "=l"(sum), "=l"(below)
           : "l"(a), "l"(b)
           : "cc"
           : out_of_range);
  return sum;
out_of_range:
  flag_saturation();
  return a < 0 ? -kMaxRaw32 : kMaxRaw32;
}
#endif

// a + b, saturated to the symmetric range.
STICKSLIP_FIXED_KERNEL constexpr std::int32_t add_raw32(std::int32_t a, std::int32_t b) noexcept {
#ifdef STICKSLIP_THUMB1_ASSEMBLY
  if (!__builtin_is_constant_evaluated()) return add_raw32_by_flags(a, b);
#endif
  return add_raw32_portable(a, b);
}

// round(a b / 2^F) from four 16 x 16 -> 32-bit products in 32-bit words only, for ARMv6-M, where
// assembling the 64-bit product and adding and shifting it in register pairs costs a dozen more
// instructions. With a = a1 2^16 + a0 and b likewise, a b = high 2^32 + mid 2^16 + (a0 b0 mod
// 2^16), where mid gathers the middle partial products' low halves and a0 b0's high half, and
// high the rest. For 17 <= F <= 31 the rounding half 2^(F-1) falls in mid's span and the bits
// below 2^16 cannot carry into the quotient: round(a b / 2^F) = high 2^(32-F) +
// floor((mid + 2^(F-17)) / 2^(F-16)). Built on the host too, where a test checks it against the
// 64-bit product.
template <int F>
STICKSLIP_FIXED_INLINE constexpr std::uint32_t round_shift_product_halves(
    std::uint32_t a, std::uint32_t b) noexcept {
  static_assert(F >= 17 && F <= 31, "the rounding half must fall above a0 b0's low half");
  const std::uint32_t a0 = a & 0xffffu, a1 = a >> 16, b0 = b & 0xffffu, b1 = b >> 16;
  const std::uint32_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  // Each term < 2^16, so mid < 2^18; high < 2^30 since a b < 2^62.
  const std::uint32_t mid = (p00 >> 16) + (p01 & 0xffffu) + (p10 & 0xffffu);
  const std::uint32_t high = p11 + (p01 >> 16) + (p10 >> 16);
  // high 2^(32-F) >= 2^31 already does not fit; below that the sum cannot wrap.
  if (high >= (std::uint32_t{1} << (F - 1))) return std::uint32_t{1} << 31;
  return (high << (32 - F)) + ((mid + (std::uint32_t{1} << (F - 17))) >> (F - 16));
}

// round(a b / 2^F) for magnitudes a, b < 2^31 (the product < 2^62), or any value above
// kMaxRaw32 when the quotient does not fit it.
template <int F>
STICKSLIP_FIXED_INLINE constexpr std::uint32_t round_shift_product(std::uint32_t a,
                                                                   std::uint32_t b) noexcept {
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
  if constexpr (F >= 17) return round_shift_product_halves<F>(a, b);
#endif
  // Both < 2^31: the product < 2^62, and adding the half cannot overflow.
  const std::uint64_t q = (multiply_32x32(a, b) + (std::uint64_t{1} << (F - 1))) >> F;
  return q > static_cast<std::uint64_t>(kMaxRaw32) ? std::uint32_t{1} << 31
                                                   : static_cast<std::uint32_t>(q);
}

// round(a b / 2^F), ties away from zero, saturated.
template <int F>
STICKSLIP_FIXED_KERNEL constexpr std::int32_t multiply_raw32(std::int32_t a,
                                                             std::int32_t b) noexcept {
  const bool negative = (a < 0) != (b < 0);
  const auto ua = static_cast<std::uint32_t>(a < 0 ? -a : a);
  const auto ub = static_cast<std::uint32_t>(b < 0 ? -b : b);
  const std::uint32_t q = round_shift_product<F>(ua, ub);
  if (q > static_cast<std::uint32_t>(kMaxRaw32)) {
    flag_saturation();
    return negative ? -kMaxRaw32 : kMaxRaw32;
  }
  return negative ? -static_cast<std::int32_t>(q) : static_cast<std::int32_t>(q);
}

// (a 2^F) / b truncated toward zero, saturated (the rational friction law only).
template <int F>
STICKSLIP_FIXED_KERNEL constexpr std::int32_t divide_raw32(std::int32_t a,
                                                           std::int32_t b) noexcept {
  if (b == 0) {
    flag_saturation();
    return a == 0 ? 0 : (a < 0 ? -kMaxRaw32 : kMaxRaw32);
  }
  return saturate32((std::int64_t{a} * (std::int64_t{1} << F)) / b);
}

// floor(sqrt(x)) to 16 significant bits, for x < 2^64: x is shifted right by an even 2k until it
// fits 32 bits, and its 32-bit integer square root (16 rounds of one compare and subtract)
// shifted back by k. On ARMv6-M a 64-bit square root costs 31 rounds of two-word arithmetic; the
// Newton steps that use this (CubicSegment) double its precision each.
STICKSLIP_FIXED_INLINE constexpr std::uint64_t square_root_16_bits(std::uint64_t x) noexcept {
  int k = 0;
  while ((x >> 32) != 0u) {
    x >>= 2;
    ++k;
  }
  auto rest = static_cast<std::uint32_t>(x);
  std::uint32_t root = 0, bit = std::uint32_t{1} << 30;
  while (bit > rest) bit >>= 2;
  while (bit != 0u) {
    if (rest >= root + bit) {
      rest -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  // root < 2^16 and k <= 16: the shift fits 32 bits (no two-word shift routine on ARMv6-M).
  return std::uint64_t{root << k};
}

// The first u in (0, 1] where c + b u + a u^2 falls through 0, given c > 0 (raw values of Q.F),
// as a raw value of Q.F; -1 where it has none there. The discriminant b^2 - 4 a c is formed
// exactly in 64 bits (Q.2F): the coefficients of an event's polynomial are often a few units of
// the format's last place, where products rounded to the format would lose it. Then one division
// without cancellation: 2 c / (|b| + sqrt) while the value falls at 0 (b < 0), else
// (b + sqrt) / (2 |a|), the root past the turning point of a rising start. No intermediate
// saturates: where an operand could overflow the arithmetic (|a| or c from 2^30, the square root
// from 2^31), there is no root either.
template <int F>
STICKSLIP_FIXED_KERNEL constexpr std::int32_t falling_quadratic_root(std::int32_t a, std::int32_t b,
                                                                     std::int32_t c) noexcept {
  const auto ua = a < 0 ? 0u - static_cast<std::uint32_t>(a) : static_cast<std::uint32_t>(a);
  const auto ub = b < 0 ? 0u - static_cast<std::uint32_t>(b) : static_cast<std::uint32_t>(b);
  const auto uc = static_cast<std::uint32_t>(c);
  if (c <= 0 || ((ua | uc) >> 30) != 0u) return -1;
  // Both terms < 2^62: neither their sum nor their difference overflows.
  const std::uint64_t b2 = multiply_32x32(ub, ub), ac4 = multiply_32x32(ua, uc) << 2;
  if (a > 0 && b2 < ac4) return -1;  // no real root
  const std::uint64_t root = square_root_16_bits(a < 0 ? b2 + ac4 : b2 - ac4);
  if ((root >> 31) != 0u) return -1;
  const auto s = static_cast<std::uint32_t>(root);
  std::uint32_t n = 0, d = 0;
  if (b < 0) {
    n = uc << 1;
    d = ub + s;  // < 2^32
  } else if (a < 0) {
    n = ub + s;
    d = ua << 1;
  } else {
    return -1;  // rising and bending up: no fall through 0
  }
  if (d == 0u || n > d || (d >> 31) != 0u) return -1;
  return static_cast<std::int32_t>(proportion_raw<F>(n, d));
}

}  // namespace fixed_point_detail

template <int FractionBits>
class FixedPoint32 {
  static_assert(FractionBits >= 8 && FractionBits <= 29, "Q(31-F).F on int32 with 8 <= F <= 29");

 public:
  using Raw = std::int32_t;
  static constexpr int kFractionBits = FractionBits;
  static constexpr int kIntegerBits = 31 - FractionBits;
  static constexpr double kScale = static_cast<double>(std::uint32_t{1} << FractionBits);
  static constexpr double max_value() noexcept {
    return static_cast<double>(std::uint32_t{1} << kIntegerBits);
  }
  static constexpr double resolution() noexcept { return 1.0 / kScale; }

  constexpr FixedPoint32() noexcept = default;
  STICKSLIP_FIXED_INLINE constexpr explicit FixedPoint32(int value) noexcept
      : raw_(from_integer(value)) {}
  constexpr explicit FixedPoint32(unsigned value) noexcept
      : raw_(from_integer(value > static_cast<unsigned>(INT32_MAX) ? std::int64_t{INT32_MAX}
                                                                   : std::int64_t{value})) {}
  constexpr explicit FixedPoint32(double value) noexcept : raw_(from_real(value)) {}

  static constexpr FixedPoint32 from_raw(Raw raw) noexcept {
    FixedPoint32 f;
    f.raw_ = raw < -fixed_point_detail::kMaxRaw32 ? -fixed_point_detail::kMaxRaw32 : raw;
    return f;
  }
  constexpr Raw raw() const noexcept { return raw_; }
  constexpr double to_double() const noexcept { return static_cast<double>(raw_) / kScale; }
  // Truncates toward zero; a negative value gives 0 (flagged).
  constexpr explicit operator unsigned() const noexcept {
    if (raw_ < 0) {
      fixed_point_detail::flag_saturation();
      return 0u;
    }
    return static_cast<unsigned>(raw_) >> FractionBits;
  }

  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint32 operator+(FixedPoint32 a,
                                                                 FixedPoint32 b) noexcept {
    return exactly(fixed_point_detail::add_raw32(a.raw_, b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint32 operator-(FixedPoint32 a,
                                                                 FixedPoint32 b) noexcept {
    return exactly(fixed_point_detail::add_raw32(a.raw_, -b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint32 operator-(FixedPoint32 a) noexcept {
    return exactly(-a.raw_);
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint32 operator*(FixedPoint32 a,
                                                                 FixedPoint32 b) noexcept {
    return exactly(fixed_point_detail::multiply_raw32<FractionBits>(a.raw_, b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint32 operator/(FixedPoint32 a,
                                                                 FixedPoint32 b) noexcept {
    return exactly(fixed_point_detail::divide_raw32<FractionBits>(a.raw_, b.raw_));
  }
  constexpr FixedPoint32& operator+=(FixedPoint32 b) noexcept { return *this = *this + b; }
  constexpr FixedPoint32& operator-=(FixedPoint32 b) noexcept { return *this = *this - b; }
  constexpr FixedPoint32& operator*=(FixedPoint32 b) noexcept { return *this = *this * b; }
  friend constexpr bool operator==(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ == b.raw_;
  }
  friend constexpr bool operator!=(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ != b.raw_;
  }
  friend constexpr bool operator<(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ < b.raw_;
  }
  friend constexpr bool operator>(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ > b.raw_;
  }
  friend constexpr bool operator<=(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ <= b.raw_;
  }
  friend constexpr bool operator>=(FixedPoint32 a, FixedPoint32 b) noexcept {
    return a.raw_ >= b.raw_;
  }

 private:
  static constexpr FixedPoint32 exactly(Raw raw) noexcept {
    FixedPoint32 f;
    f.raw_ = raw;
    return f;
  }
  STICKSLIP_FIXED_INLINE static constexpr Raw from_integer(std::int64_t value) noexcept {
    constexpr std::int64_t limit = std::int64_t{1} << kIntegerBits;
    if (value >= limit || value <= -limit) {
      fixed_point_detail::flag_saturation();
      return value < 0 ? -fixed_point_detail::kMaxRaw32 : fixed_point_detail::kMaxRaw32;
    }
    return static_cast<Raw>(value * (std::int64_t{1} << FractionBits));
  }
  static constexpr Raw from_real(double value) noexcept {
    const double scaled = value * kScale;
    constexpr double kLimit = 2147483647.5;  // rounds to 2^31 - 1 at most
    if (!(scaled < kLimit && scaled > -kLimit)) {
      fixed_point_detail::flag_saturation();
      if (!(scaled == scaled)) return 0;  // NaN
      return scaled < 0.0 ? -fixed_point_detail::kMaxRaw32 : fixed_point_detail::kMaxRaw32;
    }
    const double rounded = scaled < 0.0 ? scaled - 0.5 : scaled + 0.5;
    return static_cast<Raw>(rounded);
  }
  Raw raw_ = 0;
};

// The scalar of the Cortex-M0+ build: Q7.24 in scaled units (models/scaled_oscillator.hpp).
using Fixed32 = FixedPoint32<24>;

template <int F>
struct ScalarTraits<FixedPoint32<F>> : FixedPointTraits<FixedPoint32<F>> {
  // One tick per step, and inside it the cubic Taylor polynomial of the exact solution
  // (integrators/cubic_segment.hpp): in scene units (dt = 1) it is the exact solution to the
  // format's rounding over a whole step, so an event is located without bisecting the step.
  // Bisecting into ticks of dt/16 walks up to 31 blocks, each a step map of about 25 products:
  // 75,000 instructions per frame on the Cortex-M0+ (docs/EMBEDDED.md).
  static constexpr int kEventTickLevel = 0;
  static constexpr bool kCubicEventSearch = true;
  // The cubic search's polynomials carry no powers of dt, so the scalar runs in scene units only:
  // time in steps and mass in seat masses, dt = 1 and m = 1 (models/scaled_oscillator.hpp).
  static constexpr bool kSceneUnits = true;
  // The first u in (0, 1] where c + b u + a u^2 falls through 0 (c > 0), from the exact
  // discriminant; -1 where there is none (fixed_point_detail::falling_quadratic_root()). The
  // start of the cubic search's Newton steps.
  static FixedPoint32<F> falling_quadratic_root(FixedPoint32<F> a, FixedPoint32<F> b,
                                                FixedPoint32<F> c) noexcept {
    return FixedPoint32<F>::from_raw(
        fixed_point_detail::falling_quadratic_root<F>(a.raw(), b.raw(), c.raw()));
  }
  // The M0+ build: the common path's whole slipping step out of line, so that its temporaries
  // are not on the stack under the event search (Oscillator::whole_step_slips()).
  static constexpr bool kCompactStack = true;
};

}  // namespace stickslip
