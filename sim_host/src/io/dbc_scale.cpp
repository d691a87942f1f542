#include "dbc_scale.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <system_error>

namespace stickslip::host {
namespace {

bool digit(char c) {
  return c >= '0' && c <= '9';
}

// An exact decimal: mantissa * 10^exponent, when the text has at most 18 significant digits.
struct Decimal {
  std::int64_t mantissa = 0;
  int exponent = 0;
  bool ok = false;
};

Decimal parse_decimal(std::string_view text) {
  Decimal decimal;
  bool negative = false;
  std::size_t at = 0;
  if (at < text.size() && (text[at] == '-' || text[at] == '+')) negative = text[at++] == '-';
  std::uint64_t mantissa = 0;
  int digits = 0;
  int exponent = 0;
  bool point = false;
  bool any = false;
  for (; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (!digit(c)) break;
    any = true;
    if (mantissa == 0 && c == '0') {
      if (point) --exponent;
      continue;
    }
    if (++digits > 18) return decimal;
    mantissa = mantissa * 10u + static_cast<unsigned>(c - '0');
    if (point) --exponent;
  }
  if (!any) return decimal;
  if (at < text.size()) {
    if ((text[at] != 'e' && text[at] != 'E') || at + 1 >= text.size()) return decimal;
    int e = 0;
    const auto result = std::from_chars(text.data() + at + 1 + (text[at + 1] == '+' ? 1 : 0),
                                        text.data() + text.size(), e);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return decimal;
    if (e < -400 || e > 400) return decimal;
    exponent += e;
  }
  decimal.mantissa =
      negative ? -static_cast<std::int64_t>(mantissa) : static_cast<std::int64_t>(mantissa);
  decimal.exponent = exponent;
  decimal.ok = true;
  return decimal;
}

bool times_power_of_ten(std::int64_t value, int power, std::int64_t& out) {
  for (int i = 0; i < power; ++i)
    if (__builtin_mul_overflow(value, std::int64_t{10}, &value)) return false;
  out = value;
  return true;
}

}  // namespace

// The exact form of raw * factor + offset when both decimals share a power-of-ten denominator
// that a double holds exactly (10^22 at most): one division then rounds once, to the double
// nearest the exact decimal value, which is what a decimal-arithmetic decoder (canmatrix) gets.
DbcScale make_scale(std::string_view factor_text, std::string_view offset_text, double factor,
                    double offset) {
  DbcScale scale;
  scale.factor = factor;
  scale.offset = offset;
  const Decimal f = parse_decimal(factor_text);
  const Decimal o = parse_decimal(offset_text);
  if (!f.ok || !o.ok) return scale;
  const int common = std::min({f.exponent, o.exponent, 0});
  if (common < -22) return scale;
  std::int64_t per_raw = 0, at_zero = 0;
  if (f.exponent - common > 18 || o.exponent - common > 18) return scale;
  if (!times_power_of_ten(f.mantissa, f.exponent - common, per_raw)) return scale;
  if (!times_power_of_ten(o.mantissa, o.exponent - common, at_zero)) return scale;
  std::int64_t denominator = 0;
  times_power_of_ten(1, -common, denominator);
  scale.exact = true;
  scale.numerator_per_raw = per_raw;
  scale.numerator_offset = at_zero;
  scale.denominator = static_cast<double>(denominator);
  return scale;
}

}  // namespace stickslip::host
