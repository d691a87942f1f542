// The Q7.24 kernels as the target build compiles them (core/fixed_point32.hpp: on ARMv6-M the
// saturating add by the flags in inline assembly, the product from four 16 x 16-bit products, the
// proportion by shift-and-subtract) against reference code of the same build that shares none of
// their arithmetic: the portable sum, and 64-bit products and quotients from the compiler's
// library (__aeabi_lmul, __aeabi_uldivmod). Run on QEMU with semihosting by CTest
// embedded.kernels_match_reference_code: prints one line per kernel with its cases, those whose
// result saturates, and its mismatches (the first mismatch's operands), and exits 0 only if there
// are none. The host's tests check the
// portable code; only this check runs the target's instructions.
#include <cstdint>

#include "exact_rounding.hpp"
#include "semihosting.hpp"
#include "stickslip/core/fixed_point32.hpp"

namespace {

namespace fp = stickslip::fixed_point_detail;
using semihosting::print;
using semihosting::print_number;

constexpr int kF = 24;
constexpr std::int32_t kMax = INT32_MAX;
constexpr int kRandomCases = 200000;

// The operands that meet the kernels' boundaries: 0, +-1, the ends of the symmetric range and
// the powers of two about the half of it, and the raw values of small products' rounding ties.
constexpr std::int32_t kEdges[] = {0,
                                   1,
                                   -1,
                                   2,
                                   -2,
                                   3,
                                   kMax,
                                   -kMax,
                                   kMax - 1,
                                   -(kMax - 1),
                                   1 << 30,
                                   -(1 << 30),
                                   (1 << 30) - 1,
                                   -((1 << 30) - 1),
                                   (1 << 30) + 1,
                                   -((1 << 30) + 1),
                                   1 << 24,
                                   -(1 << 24),
                                   (1 << 24) + 1,
                                   -((1 << 24) + 1),
                                   1 << 12,
                                   -(1 << 12),
                                   1 << 11,
                                   3 << 11,
                                   -(3 << 11),
                                   0xFFFF,
                                   0x10000,
                                   -0x10000,
                                   0x7FFF8000,
                                   -0x7FFF8000,
                                   0x00B504F3,
                                   -0x00B504F3,
                                   0x0B504F33,
                                   12345678,
                                   -12345678};

std::uint32_t state = 0x9E3779B9u;
std::uint32_t next_random() {  // xorshift32
  state ^= state << 13;
  state ^= state >> 17;
  state ^= state << 5;
  return state;
}
// A raw value of the symmetric range, of random magnitude (a random shift) and sign.
std::int32_t random_raw() {
  const std::uint32_t bits = next_random() >> (next_random() % 32u);
  const auto magnitude = static_cast<std::int32_t>(bits >> 1);  // < 2^31
  return (next_random() & 1u) != 0u ? -magnitude : magnitude;
}

// a + b saturated, with its flag: the sum in 64 bits.
std::int32_t reference_add(std::int32_t a, std::int32_t b, bool& saturated) {
  const std::int64_t sum = std::int64_t{a} + b;
  saturated = sum > kMax || sum < -kMax;
  return saturated ? (sum < 0 ? -kMax : kMax) : static_cast<std::int32_t>(sum);
}
// round(a b / 2^24), ties away from zero, saturated: the 64-bit product of the compiler's library
// (__aeabi_lmul), rounded by the host tests' reference.
std::int32_t reference_multiply(std::int32_t a, std::int32_t b, bool& saturated) {
  const std::int64_t q = stickslip::test::rounded_product<kF>(std::int64_t{a}, std::int64_t{b});
  saturated = q > kMax || q < -kMax;
  return saturated ? (q < 0 ? -kMax : kMax) : static_cast<std::int32_t>(q);
}
// n / d in [0, 1] as Q.24 for 0 <= n, 0 < d, rounded to nearest, ties up: a 64-bit division of
// the compiler's library.
std::uint32_t reference_proportion(std::uint32_t n, std::uint32_t d) {
  if (n >= d) return std::uint32_t{1} << kF;
  const std::uint64_t scaled = std::uint64_t{n} << kF;
  std::uint64_t q = scaled / d;
  if (2u * (scaled - q * d) >= d) ++q;
  return static_cast<std::uint32_t>(q);
}

struct Tally {
  const char* name;
  std::uint64_t cases = 0, mismatched = 0, saturated = 0;
  std::int64_t first_a = 0, first_b = 0;
  void note(bool same, std::int64_t a, std::int64_t b, bool saturating = false) {
    ++cases;
    saturated += saturating ? 1u : 0u;
    if (!same && mismatched++ == 0) {
      first_a = a;
      first_b = b;
    }
  }
  bool report() const {
    print("kernel_check: ");
    print(name);
    print(" cases=");
    print_number(cases);
    print(" saturated=");
    print_number(saturated);
    print(" mismatched=");
    print_number(mismatched);
    if (mismatched != 0) {
      print(" first: ");
      print(first_a < 0 ? "-" : "");
      print_number(static_cast<std::uint64_t>(first_a < 0 ? -first_a : first_a));
      print(", ");
      print(first_b < 0 ? "-" : "");
      print_number(static_cast<std::uint64_t>(first_b < 0 ? -first_b : first_b));
    }
    print("\n");
    return mismatched == 0 && cases != 0;
  }
};

void check_add(Tally& tally, std::int32_t a, std::int32_t b) {
  stickslip::take_fixed_point_saturation();
  const std::int32_t got = fp::add_raw32(a, b);
  const bool got_saturated = stickslip::take_fixed_point_saturation();
  bool saturated = false;
  const std::int32_t want = reference_add(a, b, saturated);
  tally.note(got == want && got_saturated == saturated, a, b, saturated);
}
void check_multiply(Tally& tally, std::int32_t a, std::int32_t b) {
  stickslip::take_fixed_point_saturation();
  const std::int32_t got = fp::multiply_raw32<kF>(a, b);
  const bool got_saturated = stickslip::take_fixed_point_saturation();
  bool saturated = false;
  const std::int32_t want = reference_multiply(a, b, saturated);
  tally.note(got == want && got_saturated == saturated, a, b, saturated);
}
void check_proportion(Tally& tally, std::uint32_t n, std::uint32_t d) {
  if (d == 0u) return;
  tally.note(fp::proportion_raw<kF, std::uint32_t>(n, d) == reference_proportion(n, d), n, d);
}
std::uint32_t magnitude(std::int32_t v) {
  return v < 0 ? 0u - static_cast<std::uint32_t>(v) : static_cast<std::uint32_t>(v);
}

}  // namespace

extern "C" void firmware_main() {
  Tally add{"add_raw32"}, multiply{"multiply_raw32<24>"}, proportion{"proportion_raw<24>"};
  for (const std::int32_t a : kEdges) {
    for (const std::int32_t b : kEdges) {
      check_add(add, a, b);
      check_multiply(multiply, a, b);
      check_proportion(proportion, magnitude(a), magnitude(b));
    }
  }
  // Quotients on a rounding tie (n 2^24 / d = k + 1/2) and beside it: d = m 2^25.
  constexpr std::uint32_t kTieDivisorFactors[] = {1u, 3u, 5u, 63u};
  for (const std::uint32_t m : kTieDivisorFactors) {
    for (std::uint32_t n = 1; n <= 200; ++n) check_proportion(proportion, n, m << 25);
  }
  for (int i = 0; i < kRandomCases; ++i) {
    const std::int32_t a = random_raw(), b = random_raw();
    check_add(add, a, b);
    check_multiply(multiply, a, b);
    check_proportion(proportion, magnitude(a), magnitude(b));
    // Sums on and next to both ends of the range, -2^31 included (operands within the range).
    const std::int32_t near = static_cast<std::int32_t>(next_random() % 3u) - 1;
    const std::int64_t b_end = (a >= 0 ? std::int64_t{kMax} : -std::int64_t{kMax}) - a + near;
    if (b_end <= kMax && b_end >= -kMax) check_add(add, a, static_cast<std::int32_t>(b_end));
    // A quotient just below, on and above kMax after rounding: b near kMax 2^24 / a.
    if (a != 0) {
      const std::int64_t b_edge = (std::int64_t{kMax} << kF) / a + near;
      if (b_edge <= kMax && b_edge >= -kMax) {
        check_multiply(multiply, a, static_cast<std::int32_t>(b_edge));
      }
    }
    // n close to d, where the rounding decides between 1 - 2^-24 and 1.
    const std::uint32_t d = magnitude(b);
    check_proportion(proportion, d - (next_random() % 4u), d);
  }
  const bool add_ok = add.report();
  const bool multiply_ok = multiply.report();
  const bool proportion_ok = proportion.report();
  semihosting::exit_with(add_ok && multiply_ok && proportion_ok);
}
