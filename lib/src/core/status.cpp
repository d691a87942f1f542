#include "stickslip/core/status.hpp"

#include <cmath>

namespace stickslip {

const char* status_name(Status status) noexcept {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::not_finite:
      return "not finite";
    case Status::out_of_range:
      return "out of range";
    case Status::static_below_kinetic:
      return "static friction below kinetic friction";
    case Status::unstable:
      return "unstable";
    case Status::unsupported:
      return "unsupported";
  }
  return "unknown";
}

StatusMessage& StatusMessage::append(const char* text) noexcept {
  while (text != nullptr && *text != '\0' && length_ + 1 < kCapacity) text_[length_++] = *text++;
  text_[length_] = '\0';
  return *this;
}

// %g-like formatting without the C library's printf family (lib/ does no I/O): enough for
// messages, exact for the small integers and simple decimals configure() reports.
StatusMessage& StatusMessage::append(double value, int significant) noexcept {
  if (std::isnan(value)) return append("nan");
  if (std::isinf(value)) return append(value > 0 ? "inf" : "-inf");
  if (value == 0.0) return append("0");
  if (significant < 1) significant = 1;
  if (significant > 15) significant = 15;
  char buffer[40];
  int n = 0;
  if (value < 0) {
    buffer[n++] = '-';
    value = -value;
  }
  int exponent = static_cast<int>(std::floor(std::log10(value)));
  // Subnormal values: 10^exponent itself would underflow to 0 (and scaled become infinite), so
  // scale by 1e300 first.
  double scaled = exponent < -300 ? (value * 1e300) / std::pow(10.0, exponent + 300)
                                  : value / std::pow(10.0, exponent);
  // Round to `significant` digits; rounding may carry into a new leading digit.
  double factor = std::pow(10.0, significant - 1);
  double digits_value = std::nearbyint(scaled * factor);
  if (digits_value >= 10.0 * factor) {
    digits_value /= 10.0;
    ++exponent;
  }
  char digits[20];
  int count = 0;
  for (int i = 0; i < significant; ++i) {
    const double next = std::floor(digits_value / 10.0);
    digits[significant - 1 - i] =
        static_cast<char>('0' + static_cast<int>(digits_value - next * 10.0));
    digits_value = next;
    ++count;
  }
  while (count > 1 && digits[count - 1] == '0') --count;  // drop trailing zeros
  const bool scientific = exponent < -4 || exponent >= significant;
  if (scientific) {
    buffer[n++] = digits[0];
    if (count > 1) {
      buffer[n++] = '.';
      for (int i = 1; i < count; ++i) buffer[n++] = digits[i];
    }
    buffer[n++] = 'e';
    int e = exponent;
    if (e < 0) {
      buffer[n++] = '-';
      e = -e;
    } else {
      buffer[n++] = '+';
    }
    if (e >= 100) buffer[n++] = static_cast<char>('0' + e / 100);
    buffer[n++] = static_cast<char>('0' + (e / 10) % 10);
    buffer[n++] = static_cast<char>('0' + e % 10);
  } else if (exponent >= 0) {
    for (int i = 0; i <= exponent; ++i) buffer[n++] = i < count ? digits[i] : '0';
    if (count > exponent + 1) {
      buffer[n++] = '.';
      for (int i = exponent + 1; i < count; ++i) buffer[n++] = digits[i];
    }
  } else {
    buffer[n++] = '0';
    buffer[n++] = '.';
    for (int i = 0; i < -exponent - 1; ++i) buffer[n++] = '0';
    for (int i = 0; i < count; ++i) buffer[n++] = digits[i];
  }
  buffer[n] = '\0';
  return append(buffer);
}

}  // namespace stickslip
