// The digits: q = round(|v| * 10^p) with 10^16 <= q < 10^17, p = 16 - E, E the decimal exponent.
// |v| * 10^p is computed in double-double arithmetic (Dekker's exact products; this file is built
// with -ffp-contract=off so no FMA contraction breaks them), relative error < 2^-100, i.e. an
// absolute error < 1e-13 at 1e17. Rounding is decided from the fraction unless it lies within
// 1e-9 of one half (a possible tie), where fmt's exact (slow) algorithm decides instead.
#include "stickslip/host/number_format.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace stickslip::host {
namespace {

struct DoubleDouble {
  double hi, lo;
};

DoubleDouble quick_two_sum(double a, double b) noexcept {  // |a| >= |b|
  const double s = a + b;
  return {s, b - (s - a)};
}

void split(double a, double& hi, double& lo) noexcept {
  const double c = 134217729.0 * a;  // 2^27 + 1
  hi = c - (c - a);
  lo = a - hi;
}

// a * b = hi + lo exactly (Dekker 1971).
DoubleDouble two_product(double a, double b) noexcept {
  const double p = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

DoubleDouble multiply(const DoubleDouble& a, double b) noexcept {
  DoubleDouble p = two_product(a.hi, b);
  p.lo += a.lo * b;
  return quick_two_sum(p.hi, p.lo);
}

DoubleDouble reciprocal(const DoubleDouble& b) noexcept {
  const double q1 = 1.0 / b.hi;
  DoubleDouble p = two_product(q1, b.hi);
  p.lo += q1 * b.lo;
  const double remainder = (1.0 - p.hi) - p.lo;  // 1 - p.hi is exact (p.hi ~ 1)
  return quick_two_sum(q1, remainder / b.hi);
}

constexpr int kMinPower = -40;  // |v| up to ~1e56
constexpr int kMaxPower = 60;   // |v| down to ~1e-44

// 10^p as a double-double: exact for 0 <= p <= 44 (5^44 < 2^106), within ~2^-104 elsewhere.
class PowersOfTen {
 public:
  PowersOfTen() noexcept {
    std::array<double, 23> exact{};  // 10^0 .. 10^22 are exact doubles
    exact[0] = 1.0;
    for (std::size_t i = 1; i < exact.size(); ++i) exact[i] = exact[i - 1] * 10.0;
    for (int p = 0; p <= kMaxPower; ++p) {
      DoubleDouble value{};
      if (p <= 22) {
        value = {exact[static_cast<std::size_t>(p)], 0.0};
      } else if (p <= 44) {
        value = two_product(exact[22], exact[static_cast<std::size_t>(p - 22)]);
      } else {
        value =
            multiply(two_product(exact[22], exact[22]), exact[static_cast<std::size_t>(p - 44)]);
      }
      at(p) = value;
    }
    for (int p = -1; p >= kMinPower; --p) at(p) = reciprocal(at(-p));
    // Plain doubles near 10^k = 10^16 / 10^(16-k), for choosing the exponent (verified later).
    for (int k = 16 - kMaxPower; k <= 16 - kMinPower; ++k) {
      const DoubleDouble& inverse = at(16 - k);  // 10^(16-k)
      plain_[static_cast<std::size_t>(k - (16 - kMaxPower))] = 1e16 / (inverse.hi + inverse.lo);
    }
  }
  const DoubleDouble& operator[](int p) const noexcept {
    return table_[static_cast<std::size_t>(p - kMinPower)];
  }
  // 10^k, rounded to a double, for 16 - kMaxPower <= k <= 16 - kMinPower.
  double approximate(int k) const noexcept {
    return plain_[static_cast<std::size_t>(k - (16 - kMaxPower))];
  }

 private:
  DoubleDouble& at(int p) noexcept { return table_[static_cast<std::size_t>(p - kMinPower)]; }
  std::array<DoubleDouble, kMaxPower - kMinPower + 1> table_{};
  std::array<double, kMaxPower - kMinPower + 1> plain_{};
};

// Built once at start-up (a namespace-scope object: no initialisation guard on the hot path).
const PowersOfTen kPowersOfTen;

// Two decimal digits at a time.
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "80818283848586878889909192939495969798990";

// Writes `value` < 10^count as exactly `count` digits (count even), most significant first.
void write_digits(std::uint32_t value, int count, char* out) noexcept {
  for (int i = count - 2; i >= 0; i -= 2) {
    const std::uint32_t pair = value % 100;
    value /= 100;
    out[i] = kDigitPairs[2 * pair];
    out[i + 1] = kDigitPairs[2 * pair + 1];
  }
}

// floor(x) for |x| < 2^62 without a libm call (baseline x86-64 has no rounding instruction).
std::int64_t floor_to_int(double x) noexcept {
  const auto truncated = static_cast<std::int64_t>(x);
  return static_cast<double>(truncated) > x ? truncated - 1 : truncated;
}

constexpr std::int64_t kLowest17 = 10000000000000000;   // 10^16
constexpr std::int64_t kBeyond17 = 100000000000000000;  // 10^17

char* format_slow(double value, char* out) noexcept {
  const auto result = fmt::format_to_n(out, kMaxG17Chars - 1, "{:.17g}", value);
  return result.out;
}

// The 17 significant digits q (10^16 <= q < 10^17) and decimal exponent of |value| > 0, or false
// when the rounding cannot be decided here.
bool seventeen_digits(double magnitude, std::int64_t& q, int& exponent10) noexcept {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &magnitude, sizeof bits);
  const int exponent2 = static_cast<int>(bits >> 52) - 1023;  // magnitude in [2^e2, 2^(e2+1))
  if (exponent2 == -1023) return false;                       // subnormal: the slow path
  // floor(e2 log10(2)) (exact for |e2| < 1700): the decimal exponent or one below it.
  int e = (exponent2 * 78913) >> 18;
  const PowersOfTen& powers = kPowersOfTen;
  // One compare settles the exponent almost always (the loop below still verifies it), which
  // saves a second double-double product for half of all values.
  if (e + 1 >= 16 - kMaxPower && e + 1 <= 16 - kMinPower &&
      magnitude >= powers.approximate(e + 1)) {
    ++e;
  }
  for (int attempt = 0; attempt < 4; ++attempt) {
    const int p = 16 - e;
    if (p < kMinPower || p > kMaxPower) return false;
    const DoubleDouble scaled = multiply(powers[p], magnitude);
    if (!(scaled.hi >= 0x1.0p53) || scaled.hi > 2.0e17) {  // far off: adjust the exponent
      e += scaled.hi > 2.0e17 ? 1 : -1;
      continue;
    }
    // scaled.hi >= 2^53 is an integer; the fraction lives in scaled.lo.
    const std::int64_t whole_lo = floor_to_int(scaled.lo);
    const double fraction = scaled.lo - static_cast<double>(whole_lo);
    if (std::fabs(fraction - 0.5) < 1e-9) return false;  // a tie or too close to call
    std::int64_t digits = static_cast<std::int64_t>(scaled.hi) + whole_lo;
    if (fraction > 0.5) ++digits;
    if (digits < kLowest17) {
      --e;
      continue;
    }
    if (digits > kBeyond17) {
      ++e;
      continue;
    }
    if (digits == kBeyond17) {  // rounded up to the next power of ten
      digits = kLowest17;
      ++e;
    }
    q = digits;
    exponent10 = e;
    return true;
  }
  return false;
}

}  // namespace

char* format_g17(double value, char* out) noexcept {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  // Classified by bits: no floating-point compare touches a NaN.
  if (((bits >> 52) & 0x7FF) == 0x7FF) return format_slow(value, out);
  const bool negative = (bits >> 63) != 0;
  if ((bits << 1) == 0) {  // +0 or -0
    if (negative) *out++ = '-';
    *out++ = '0';
    return out;
  }
  std::int64_t q = 0;
  int exponent10 = 0;
  if (!seventeen_digits(std::fabs(value), q, exponent10)) return format_slow(value, out);

  char digits[17];
  const auto high = static_cast<std::uint32_t>(q / 100000000);  // < 10^9
  const auto low = static_cast<std::uint32_t>(q % 100000000);
  digits[0] = static_cast<char>('0' + high / 100000000);
  write_digits(high % 100000000, 8, digits + 1);
  write_digits(low, 8, digits + 9);
  int last = 16;  // %g drops trailing zeros
  while (last > 0 && digits[last] == '0') --last;

  if (negative) *out++ = '-';
  if (exponent10 < -4 || exponent10 >= 17) {  // scientific, as %g chooses for precision 17
    *out++ = digits[0];
    if (last > 0) {
      *out++ = '.';
      for (int i = 1; i <= last; ++i) *out++ = digits[i];
    }
    *out++ = 'e';
    int magnitude = exponent10;
    *out++ = magnitude < 0 ? '-' : '+';
    if (magnitude < 0) magnitude = -magnitude;
    if (magnitude >= 100) *out++ = static_cast<char>('0' + magnitude / 100);
    *out++ = static_cast<char>('0' + (magnitude / 10) % 10);
    *out++ = static_cast<char>('0' + magnitude % 10);
  } else if (exponent10 >= 0) {
    for (int i = 0; i <= exponent10; ++i) *out++ = digits[i];
    if (last > exponent10) {
      *out++ = '.';
      for (int i = exponent10 + 1; i <= last; ++i) *out++ = digits[i];
    }
  } else {
    *out++ = '0';
    *out++ = '.';
    for (int i = 1; i < -exponent10; ++i) *out++ = '0';
    for (int i = 0; i <= last; ++i) *out++ = digits[i];
  }
  return out;
}

}  // namespace stickslip::host
