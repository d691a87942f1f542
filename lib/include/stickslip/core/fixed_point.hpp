// A saturating fixed-point scalar for MCUs without an FPU: the oscillator, the friction laws and
// the integrators run with it from the same source as with float and double.
//
// Why Q23.40 on int64 and not Q-format on int32: the step multiplies coefficients that span 13
// decades in SI units (the input's effect on x_r over 1 ms, dt^2/6 = 1.7e-7, up to the stiffness
// 1.15e4 N/m) with one scalar type. A 32-bit word cannot hold both with useful precision, and the
// template source must not know per-variable scales. 23 integer bits hold +-8.4e6 (forces, k, m,
// 1/dt); 40 fraction bits resolve 9.1e-13 (x_r in metres, the map coefficients). configure()
// checks both ends for the scene and refuses it, naming the quantity, where a value would not fit
// (integrators/fixed_point_scaling.hpp).
//
// @par Scaling and overflow (every operation; a, b in Q23.40, raw values r_a, r_b in int64)
// - Range: the raw value is kept in [-(2^63 - 1), 2^63 - 1], symmetric, so negation and abs never
//   overflow. Any result outside that range saturates to the nearest end and sets the sticky
//   saturation flag (fixed_point_saturated()), like the Q flag of the Arm APSR: never a silent
//   wrap-around.
// - a + b, a - b: exact in Q23.40; saturate on overflow.
// - a * b: the exact 126-bit product (Q46.80, formed from four 32 x 32 -> 64-bit partial products,
//   no __int128, so that host and Cortex-M compute the same bits), rounded to Q23.40 to nearest,
//   ties away from zero (symmetric: (-a) * b == -(a * b)); saturate on overflow.
// - a / b: no divide instruction. 1/b is formed from b's leading 32 bits (normalised by a count of
//   leading zeros) with a linear seed 48/17 - 32/17 mu (relative error <= 1/17) and three
//   Newton-Raphson steps r <- r (2 - mu r) in 64-bit integer arithmetic; the quotient is then the
//   126-bit product a * r shifted into Q23.40, rounded to nearest (ties away from zero). Relative
//   error of the quotient <= 2^-29 (b's truncation to 32 bits 2^-31, the reciprocal 2^-30; tested),
//   plus the final rounding to 1 ulp. b == 0 saturates to +-max (0/0 gives 0) and sets the flag.
//   Used only by the rational friction law; the event instants of the step use proportion().
// - proportion(n, d) for 0 <= n <= d: n/d in [0, 1] by 40 rounds of shift-and-subtract, rounded
//   to nearest (ties up): no division in the stick-slip step.
// - Conversions: from double rounds to nearest (ties away from zero); from int/unsigned is exact;
//   both saturate and flag out of range (in a constant expression an out-of-range literal does not
//   compile). to_double is exact to double's 53 bits. Conversion to unsigned truncates toward
//   zero, negative values give 0 and set the flag.
// - Comparisons are exact.
//
// The flag is one per thread on a hosted build (thread_local) and one per core on bare metal; the
// Oscillator takes it after each step (take_fixed_point_saturation()) and counts the steps in
// which anything saturated, so a run reports saturation per oscillator.
#pragma once

#include <climits>
#include <cstdint>
#include <type_traits>

#include "stickslip/core/scalar.hpp"

namespace stickslip {

namespace fixed_point_detail {

static_assert((std::int64_t{-5} >> 1) == -3, "arithmetic right shift of negative values");

#if defined(__arm__) && !defined(__linux__)
inline bool saturated = false;  // bare metal: no threads, one flag per core
#else
inline thread_local bool saturated = false;
#endif

// Not constexpr on purpose: reaching it in a constant expression (an out-of-range literal) is a
// compile error; at run time it sets the sticky flag.
inline void flag_saturation() noexcept {
  saturated = true;
}

constexpr std::int64_t kMaxRaw = INT64_MAX;

// 128-bit unsigned value as two 64-bit halves.
struct Wide {
  std::uint64_t hi;
  std::uint64_t lo;
};

// Size-optimised builds (-Os, the MCU presets) keep the arithmetic kernels out of line: they
// take and return plain int64 (in registers under the Arm procedure call standard, where a class
// would be returned through memory), and each is then in flash once.
// Their parts, and the operators around them, are always inlined (a call per partial product
// would cost more than the product).
#if defined(__OPTIMIZE_SIZE__) && (defined(__GNUC__) || defined(__clang__))
#define STICKSLIP_FIXED_KERNEL __attribute__((noinline))
#define STICKSLIP_FIXED_INLINE __attribute__((always_inline)) inline
#else
#define STICKSLIP_FIXED_KERNEL
#define STICKSLIP_FIXED_INLINE inline
#endif

// GCC's ARMv6-M code may take a kernel's instructions from inline assembly, where the carry and
// overflow flags do what C++ cannot say (clang takes the portable code). GCC hands Thumb-1 inline
// assembly over in divided syntax unless -masm-syntax-unified: such a block switches to unified
// syntax and back.
#if (defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)) && defined(__GNUC__) && \
    !defined(__clang__)
#define STICKSLIP_THUMB1_ASSEMBLY 1
#ifdef __ARM_ASM_SYNTAX_UNIFIED__
#define STICKSLIP_THUMB1_UNIFIED_BEGIN ""
#define STICKSLIP_THUMB1_UNIFIED_END ""
#else
#define STICKSLIP_THUMB1_UNIFIED_BEGIN ".syntax unified\n\t"
#define STICKSLIP_THUMB1_UNIFIED_END "\n\t.syntax divided"
#endif
#endif

// Exact a * b for 32-bit a, b. ARMv6-M (Cortex-M0/M0+) has only a 32 x 32 -> 32-bit multiply,
// and the compiler would call its 64 x 64 -> 64-bit library routine: four 16 x 16 -> 32-bit
// products instead, inline. Elsewhere (UMULL, x86-64) the compiler's product is one instruction.
STICKSLIP_FIXED_INLINE constexpr std::uint64_t multiply_32x32(std::uint32_t a,
                                                              std::uint32_t b) noexcept {
#if defined(__ARM_ARCH_6M__) || defined(__ARM_ARCH_8M_BASE__)
  const std::uint32_t a0 = a & 0xffffu, a1 = a >> 16, b0 = b & 0xffffu, b1 = b >> 16;
  const std::uint32_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  const std::uint32_t mid = (p00 >> 16) + (p01 & 0xffffu) + (p10 & 0xffffu);
  const std::uint32_t lo = (mid << 16) | (p00 & 0xffffu);
  const std::uint32_t hi = p11 + (p01 >> 16) + (p10 >> 16) + (mid >> 16);
  return (std::uint64_t{hi} << 32) | lo;
#else
  return std::uint64_t{a} * b;
#endif
}

// Exact a * b for a, b < 2^64 from four 32 x 32 -> 64-bit products (no __int128: the host and a
// 32-bit MCU compute the same bits the same way).
STICKSLIP_FIXED_INLINE constexpr Wide multiply_wide(std::uint64_t a, std::uint64_t b) noexcept {
  const auto a0 = static_cast<std::uint32_t>(a), a1 = static_cast<std::uint32_t>(a >> 32);
  const auto b0 = static_cast<std::uint32_t>(b), b1 = static_cast<std::uint32_t>(b >> 32);
  // Many operands fit in 32 bits (coefficients such as dt, dt^2/6; anything below 2^-8 in
  // Q23.40): their high partial products are zero and skipped.
  const std::uint64_t p00 = multiply_32x32(a0, b0);
  const std::uint64_t p01 = b1 != 0u ? multiply_32x32(a0, b1) : 0u;
  const std::uint64_t p10 = a1 != 0u ? multiply_32x32(a1, b0) : 0u;
  const std::uint64_t p11 = (a1 != 0u && b1 != 0u) ? multiply_32x32(a1, b1) : 0u;
  const std::uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
  return {p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32), (mid << 32) | (p00 & 0xffffffffu)};
}

// round(w / 2^shift), ties away from zero (w is a magnitude), 0 < shift < 64; saturates at kMaxRaw.
STICKSLIP_FIXED_INLINE constexpr std::int64_t round_shift_magnitude(Wide w, int shift,
                                                                    bool& overflow) noexcept {
  const std::uint64_t half = std::uint64_t{1} << (shift - 1);
  const std::uint64_t lo = w.lo + half;
  const std::uint64_t hi = w.hi + (lo < half ? 1u : 0u);
  if ((hi >> shift) != 0u) {
    overflow = true;
    return kMaxRaw;
  }
  const std::uint64_t q = (hi << (64 - shift)) | (lo >> shift);
  if (q > static_cast<std::uint64_t>(kMaxRaw)) {
    overflow = true;
    return kMaxRaw;
  }
  return static_cast<std::int64_t>(q);
}

STICKSLIP_FIXED_INLINE constexpr std::uint64_t magnitude(std::int64_t raw) noexcept {
  return raw < 0 ? static_cast<std::uint64_t>(-raw) : static_cast<std::uint64_t>(raw);
}

constexpr int count_leading_zeros(std::uint64_t value) noexcept {
  int n = 0;
  if ((value >> 32) == 0u) {
    n += 32;
    value <<= 32;
  }
  if ((value >> 48) == 0u) {
    n += 16;
    value <<= 16;
  }
  if ((value >> 56) == 0u) {
    n += 8;
    value <<= 8;
  }
  if ((value >> 60) == 0u) {
    n += 4;
    value <<= 4;
  }
  if ((value >> 62) == 0u) {
    n += 2;
    value <<= 2;
  }
  if ((value >> 63) == 0u) n += 1;
  return n;
}

// r ~= 2^63 / m for m in [2^31, 2^32) (mu = m / 2^32 in [0.5, 1), r = 2^31 / mu in (2^31, 2^32]):
// linear seed, three Newton-Raphson steps; relative error below 2^-30.
constexpr std::uint64_t reciprocal_q31(std::uint64_t m) noexcept {
  constexpr std::uint64_t kSeedOffset = 6063890299u;  // 48/17 * 2^31
  constexpr std::uint64_t kSeedSlope = 4042593539u;   // 32/17 * 2^31
  std::uint64_t r = kSeedOffset - ((kSeedSlope * m) >> 32);
  for (int iteration = 0; iteration < 3; ++iteration) {
    // e = 2^63 (1 - mu r / 2^31), |e| < 2^62; r += r e / 2^63, with e's low 32 bits dropped.
    const std::int64_t e = static_cast<std::int64_t>((std::uint64_t{1} << 63) - m * r);
    const std::int64_t correction = (static_cast<std::int64_t>(r) * (e >> 32)) >> 31;
    r = static_cast<std::uint64_t>(static_cast<std::int64_t>(r) + correction);
  }
  return r;
}

// Saturating a + b for a, b in the symmetric range.
STICKSLIP_FIXED_KERNEL constexpr std::int64_t add_raw(std::int64_t a, std::int64_t b) noexcept {
  // The sum's magnitude is < 2^64: test before adding.
  if (b > 0 && a > kMaxRaw - b) {
    flag_saturation();
    return kMaxRaw;
  }
  if (b < 0 && a < -kMaxRaw - b) {
    flag_saturation();
    return -kMaxRaw;
  }
  return a + b;
}

// round(a b / 2^F), ties away from zero, saturated.
template <int F>
STICKSLIP_FIXED_KERNEL constexpr std::int64_t multiply_raw(std::int64_t a,
                                                           std::int64_t b) noexcept {
  // Exact shortcuts (the same result as the general path): the step multiplies by a direction
  // +-1 and by zero state components often.
  constexpr std::int64_t one = std::int64_t{1} << F;
  if (a == 0 || b == 0) return 0;
  if (b == one) return a;
  if (b == -one) return -a;
  if (a == one) return b;
  if (a == -one) return -b;
  bool overflow = false;
  const std::int64_t q =
      round_shift_magnitude(multiply_wide(magnitude(a), magnitude(b)), F, overflow);
  if (overflow) flag_saturation();
  return (a < 0) != (b < 0) ? -q : q;
}

// a 2^F / b through the reciprocal of b's leading 32 bits (see the file comment), saturated.
template <int F>
STICKSLIP_FIXED_KERNEL constexpr std::int64_t divide_raw(std::int64_t a, std::int64_t b) noexcept {
  if (b == 0) {
    flag_saturation();
    return a == 0 ? 0 : (a < 0 ? -kMaxRaw : kMaxRaw);
  }
  const bool negative = (a < 0) != (b < 0);
  const std::uint64_t ua = magnitude(a), ub = magnitude(b);
  const int zeros = count_leading_zeros(ub);    // >= 1
  const std::uint64_t m = (ub << zeros) >> 32;  // b's leading 32 bits, in [2^31, 2^32)
  const std::uint64_t r = reciprocal_q31(m);    // 2^63 / m
  // b ~= m 2^(32 - zeros), so a / b * 2^F ~= ua r 2^(zeros - 95 + F).
  const Wide product = multiply_wide(ua, r);
  const int shift = 95 - F - zeros;
  bool overflow = false;
  std::int64_t q = 0;
  if (shift > 0) {
    q = round_shift_magnitude(product, shift, overflow);
  } else {
    // Left shift by -shift (at most 62 - F): the quotient is >= 2^(62 - F) ulp in magnitude.
    const int left = -shift;
    const bool fits = product.hi == 0u && (left == 0 || (product.lo >> (63 - left)) == 0u);
    overflow = !fits;
    q = fits ? static_cast<std::int64_t>(product.lo << left) : kMaxRaw;
  }
  if (overflow) flag_saturation();
  return negative ? -q : q;
}

// One round of the restoring division: the next quotient bit.
template <typename U>
STICKSLIP_FIXED_INLINE constexpr void division_round(U& r, U& q, U d) noexcept {
  r <<= 1;
  q <<= 1;
  if (r >= d) {
    r -= d;
    q |= 1u;
  }
}

#ifdef STICKSLIP_THUMB1_ASSEMBLY
// The rounds of proportion_raw() below for 32-bit words by the carry: CMP leaves the quotient bit
// in the carry, which SUBS keeps and ADCS shifts into the quotient, 4 or 5 instructions a round
// where the portable round takes 6 or 7 with its loop. For 0 <= n < d < 2^31. Checked against
// a 64-bit division on the target (port/baremetal/src/kernel_check.cpp, CTest
// embedded.kernels_match_reference_code).
template <int F>
STICKSLIP_FIXED_INLINE std::uint32_t proportion_rounds_by_carry(std::uint32_t n,
                                                                std::uint32_t d) noexcept {
  std::uint32_t r = n, q = 0;
  const std::uint32_t zero = 0;
  asm(STICKSLIP_THUMB1_UNIFIED_BEGIN
      ".rept %c[rounds]\n\t"
      "lsls %[r], %[r], #1\n\t"
      "cmp %[r], %[d]\n\t"
      "bcc 1f\n\t"
      "subs %[r], %[r], %[d]\n"
      "1:\n\t"
      "adcs %[q], %[q]\n\t"
      ".endr\n\t"
      // Round to nearest, ties up: the carry of 2 r >= d.
      "lsls %[r], %[r], #1\n\t"
      "cmp %[r], %[d]\n\t"
      "adcs %[q], %[zero]" STICKSLIP_THUMB1_UNIFIED_END
      : [r] "+&l"(r), [q] "+&l"(q)
      : [d] "l"(d), [zero] "l"(zero), [rounds] "i"(F)
      // Early clobbers: r and q are written before d and zero are last read, and zero must not
      // share q's register (both hold 0 on entry).
      : "cc");
  return q;
}
#endif

// round(n / d 2^F) for 0 <= n, 0 < d < 2^(bits - 1) (unsigned magnitudes), clamped to [0, 2^F]:
// F rounds of restoring shift-and-subtract, ties rounded up; n >= d gives exactly 2^F. The event
// instants of the step (a fraction of a tick or of the step), where a division would need a
// divide routine on a core without one.
template <int F, typename U>
STICKSLIP_FIXED_KERNEL constexpr U proportion_raw(U n, U d) noexcept {
  if (n >= d) return U{1} << F;
#ifdef STICKSLIP_THUMB1_ASSEMBLY
  if constexpr (sizeof(U) == 4) {
    if (!__builtin_is_constant_evaluated()) return proportion_rounds_by_carry<F>(n, d);
  }
#endif
  U q = 0;
  U r = n;  // r < d throughout, so 2 r does not overflow
  // Four rounds per pass: on ARMv6-M the loop's count and branch were a third of each round.
  int bit = 0;
  for (; bit + 4 <= F; bit += 4) {
    division_round(r, q, d);
    division_round(r, q, d);
    division_round(r, q, d);
    division_round(r, q, d);
  }
  for (; bit < F; ++bit) division_round(r, q, d);
  if ((r << 1) >= d) ++q;  // round to nearest
  return q;
}

}  // namespace fixed_point_detail

// Reads and clears the sticky saturation flag of this thread (this core on bare metal).
inline bool take_fixed_point_saturation() noexcept {
  const bool was = fixed_point_detail::saturated;
  fixed_point_detail::saturated = false;
  return was;
}
// Reads the flag without clearing it.
inline bool fixed_point_saturated() noexcept {
  return fixed_point_detail::saturated;
}

template <int FractionBits>
class FixedPoint {
  // F >= 31 keeps the quotient's shift below 64 (divide_raw); F <= 61 leaves an integer bit.
  static_assert(FractionBits >= 31 && FractionBits <= 61, "Q(63-F).F on int64 with 31 <= F <= 61");

 public:
  using Raw = std::int64_t;
  static constexpr int kFractionBits = FractionBits;
  static constexpr int kIntegerBits = 63 - FractionBits;
  static constexpr double kScale = static_cast<double>(std::uint64_t{1} << FractionBits);
  // Largest magnitude (2^kIntegerBits - 1 ulp) and resolution (1 ulp), as doubles.
  static constexpr double max_value() noexcept {
    return static_cast<double>(std::uint64_t{1} << kIntegerBits);
  }
  static constexpr double resolution() noexcept { return 1.0 / kScale; }

  constexpr FixedPoint() noexcept = default;
  constexpr explicit FixedPoint(int value) noexcept : raw_(from_integer(value)) {}
  constexpr explicit FixedPoint(unsigned value) noexcept
      : raw_(from_integer(static_cast<std::int64_t>(value))) {}
  // Rounds to nearest, ties away from zero; saturates and flags out of range (NaN gives 0,
  // flagged).
  constexpr explicit FixedPoint(double value) noexcept : raw_(from_real(value)) {}

  static constexpr FixedPoint from_raw(Raw raw) noexcept {
    FixedPoint f;
    f.raw_ = raw < -fixed_point_detail::kMaxRaw ? -fixed_point_detail::kMaxRaw : raw;
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
    const std::uint64_t whole = static_cast<std::uint64_t>(raw_) >> FractionBits;
    if (whole > UINT_MAX) {
      fixed_point_detail::flag_saturation();
      return UINT_MAX;
    }
    return static_cast<unsigned>(whole);
  }

  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint operator+(FixedPoint a,
                                                               FixedPoint b) noexcept {
    return exactly(fixed_point_detail::add_raw(a.raw_, b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint operator-(FixedPoint a,
                                                               FixedPoint b) noexcept {
    return exactly(fixed_point_detail::add_raw(a.raw_, -b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint operator-(FixedPoint a) noexcept {
    return exactly(-a.raw_);
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint operator*(FixedPoint a,
                                                               FixedPoint b) noexcept {
    return exactly(fixed_point_detail::multiply_raw<FractionBits>(a.raw_, b.raw_));
  }
  friend STICKSLIP_FIXED_INLINE constexpr FixedPoint operator/(FixedPoint a,
                                                               FixedPoint b) noexcept {
    return exactly(fixed_point_detail::divide_raw<FractionBits>(a.raw_, b.raw_));
  }
  constexpr FixedPoint& operator+=(FixedPoint b) noexcept { return *this = *this + b; }
  constexpr FixedPoint& operator-=(FixedPoint b) noexcept { return *this = *this - b; }
  constexpr FixedPoint& operator*=(FixedPoint b) noexcept { return *this = *this * b; }

  // (FixedPoint32 spells these out too: the same set from an empty CRTP base makes GCC's ARMv6-M
  // step 174 bytes larger, with a memset of the event search's locals.)
  friend constexpr bool operator==(FixedPoint a, FixedPoint b) noexcept { return a.raw_ == b.raw_; }
  friend constexpr bool operator!=(FixedPoint a, FixedPoint b) noexcept { return a.raw_ != b.raw_; }
  friend constexpr bool operator<(FixedPoint a, FixedPoint b) noexcept { return a.raw_ < b.raw_; }
  friend constexpr bool operator>(FixedPoint a, FixedPoint b) noexcept { return a.raw_ > b.raw_; }
  friend constexpr bool operator<=(FixedPoint a, FixedPoint b) noexcept { return a.raw_ <= b.raw_; }
  friend constexpr bool operator>=(FixedPoint a, FixedPoint b) noexcept { return a.raw_ >= b.raw_; }

 private:
  // A raw value already in the symmetric range (what the kernels return).
  static constexpr FixedPoint exactly(Raw raw) noexcept {
    FixedPoint f;
    f.raw_ = raw;
    return f;
  }
  static constexpr Raw from_integer(std::int64_t value) noexcept {
    constexpr std::int64_t limit = std::int64_t{1} << kIntegerBits;
    if (value >= limit || value <= -limit) {
      fixed_point_detail::flag_saturation();
      return value < 0 ? -fixed_point_detail::kMaxRaw : fixed_point_detail::kMaxRaw;
    }
    return value * (std::int64_t{1} << FractionBits);
  }
  static constexpr Raw from_real(double value) noexcept {
    const double scaled = value * kScale;
    constexpr double kLimit = 9223372036854775808.0;  // 2^63
    if (!(scaled < kLimit && scaled > -kLimit)) {
      fixed_point_detail::flag_saturation();
      if (!(scaled == scaled)) return 0;  // NaN
      return scaled < 0.0 ? -fixed_point_detail::kMaxRaw : fixed_point_detail::kMaxRaw;
    }
    const double rounded = scaled < 0.0 ? scaled - 0.5 : scaled + 0.5;
    // (Near 2^63 the + 0.5 rounds back into range.)
    if (!(rounded < kLimit && rounded > -kLimit)) {
      fixed_point_detail::flag_saturation();
      return rounded < 0.0 ? -fixed_point_detail::kMaxRaw : fixed_point_detail::kMaxRaw;
    }
    return static_cast<Raw>(rounded);
  }
  Raw raw_ = 0;
};

// The fixed-point scalar of the library: Q23.40 (see above).
using Fixed = FixedPoint<40>;

// The scalar traits both fixed-point formats share (T: FixedPoint<F> or FixedPoint32<F>).
template <typename T>
struct FixedPointTraits {
  // The event search bisects on the dyadic grid and interpolates inside the last tick (the
  // integer path: no Taylor polynomials with coefficients below the resolution).
  static constexpr bool kTaylorEventSearch = false;
  // Q7.24 in scene units overrides: one tick per step, the cubic polynomial inside it.
  static constexpr bool kCubicEventSearch = false;
  // Parameters in SI units; Q7.24 overrides: scene units.
  static constexpr bool kSceneUnits = false;
  static constexpr bool kTracksSaturation = true;
  // Reads and clears the sticky saturation flag (the oscillator, after each step).
  static bool take_saturation() noexcept { return take_fixed_point_saturation(); }
  static T from_double(double value) noexcept { return T(value); }
  static constexpr double to_double(T value) noexcept { return value.to_double(); }
  static constexpr bool is_finite(T /*value*/) noexcept { return true; }
  STICKSLIP_FIXED_INLINE static constexpr T abs(T value) noexcept {
    return value < T() ? -value : value;
  }
  static constexpr T epsilon() noexcept { return T::from_raw(1); }
  // n/d clamped to [0, 1] (0 when n and d differ in sign or d == 0): the in-step event instants,
  // by F rounds of shift-and-subtract (fixed_point_detail::proportion_raw), not a division.
  static constexpr T proportion(T n, T d) noexcept {
    if (d == T() || (n < T()) != (d < T()) || n == T()) return T();
    return T::from_raw(static_cast<typename T::Raw>(
        fixed_point_detail::proportion_raw<T::kFractionBits>(magnitude(n), magnitude(d))));
  }
  // v / 2^shift (0 < shift < F), rounded as the product by 2^-shift rounds (to nearest, ties away
  // from zero), to the same bits, without a multiply: the halves and quarters of the Q7.24 event
  // search (integrators/cubic_segment.hpp).
  static constexpr T divide_by_power_of_two(T v, int shift) noexcept {
    using Raw = typename T::Raw;
    const auto q = static_cast<Raw>((magnitude(v) + (Magnitude{1} << (shift - 1))) >> shift);
    return T::from_raw(v.raw() < 0 ? -q : q);
  }
  // No transcendental functions: the atan, tanh and erf laws and Stribeck are not offered in
  // fixed point (configure() refuses them).

 private:
  using Magnitude = std::make_unsigned_t<typename T::Raw>;
  // |v| as an unsigned raw value (the symmetric range: -raw never overflows).
  static constexpr Magnitude magnitude(T v) noexcept {
    const auto raw = v.raw();
    return raw < 0 ? static_cast<Magnitude>(Magnitude{0} - static_cast<Magnitude>(raw))
                   : static_cast<Magnitude>(raw);
  }
};

template <int F>
struct ScalarTraits<FixedPoint<F>> : FixedPointTraits<FixedPoint<F>> {
  // Ticks of dt/2^10 (1 us at dt = 1 ms): on the 120 s scenes T_ax and p stay within 1e-10 of
  // double, as with dt/2^16, while an event costs about 2/3 of the instructions (each bisection
  // level is a full step map of 64-bit products).
  static constexpr int kEventTickLevel = 10;
  // Q23.40 runs on cores with room (and the host): the common path stays inline.
  static constexpr bool kCompactStack = false;
};

}  // namespace stickslip
