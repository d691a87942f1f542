#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "stickslip/host/io/number_format.hpp"
#include "stickslip/host/signals/random.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::format_g17;

namespace {

std::string fast(double value) {
  char buffer[stickslip::host::kMaxG17Chars];
  char* end = format_g17(value, buffer);
  return std::string(buffer, end);
}

std::string reference(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

double from_bits(std::uint64_t bits) {
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

}  // namespace

// The CSV files promise printf's "%.17g" exactly; the fast path must never differ from it.
TEST_GROUP(NumberFormat){};

TEST(NumberFormat, MatchesPrintfOnSpecialValues) {
  const double values[] = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.1,
                           0.001,
                           3.0 * 0.001,
                           1e-4,
                           1e-5,
                           123456789012345678.0,
                           1e16,
                           1e17,
                           9.9999999999999995e16,
                           99999999999999999.0,
                           0.5,
                           45.0,
                           88.4,
                           11500.0,
                           1e22,
                           1e23,
                           1e-40,
                           1e56,
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::epsilon(),
                           2.5,
                           0.125,
                           1.0 / 3.0};
  for (double value : values) STRCMP_EQUAL(reference(value).c_str(), fast(value).c_str());
}

TEST(NumberFormat, MatchesPrintfOnTimeGrids) {
  for (int n = 0; n < 20000; ++n) {
    const double t = static_cast<double>(n) * 0.001;
    STRCMP_EQUAL(reference(t).c_str(), fast(t).c_str());
    const double u = static_cast<double>(n) * 1e-5;
    STRCMP_EQUAL(reference(u).c_str(), fast(u).c_str());
  }
}

TEST(NumberFormat, MatchesPrintfOnRandomBitPatterns) {
  stickslip::host::Xoshiro256StarStar random(2024);
  int checked = 0;
  while (checked < 300000) {
    const std::uint64_t bits = random.next();
    // Skip infinities and NaNs by their bits: even std::isfinite raises FE_INVALID on a signaling
    // NaN.
    if (((bits >> 52) & 0x7FF) == 0x7FF) continue;
    const double value = from_bits(bits);
    ++checked;
    const std::string expected = reference(value);
    const std::string actual = fast(value);
    if (expected != actual) STRCMP_EQUAL(expected.c_str(), actual.c_str());
  }
}

TEST(NumberFormat, MatchesPrintfOnRandomMagnitudesOfSimulatedSignals) {
  stickslip::host::Xoshiro256StarStar random(7);
  for (int i = 0; i < 300000; ++i) {
    // Mantissa in [1, 2) times 2^k for k in [-60, 30]: the range of positions, velocities, forces.
    const double mantissa = 1.0 + random.uniform();
    const int exponent = static_cast<int>(random.next() % 91) - 60;
    const double value = std::ldexp(mantissa, exponent) * ((random.next() & 1) ? 1.0 : -1.0);
    const std::string expected = reference(value);
    const std::string actual = fast(value);
    if (expected != actual) STRCMP_EQUAL(expected.c_str(), actual.c_str());
  }
}

TEST(NumberFormat, ExactDecimalTiesFollowPrintf) {
  // Doubles whose 18th significant digit is an exact 5: 2^-k has long exact expansions; k*2^-1
  // with 17+ digits exercises round-half-even in the slow path.
  for (int k = 1; k < 80; ++k) {
    const double value = std::ldexp(1.0, -k);
    STRCMP_EQUAL(reference(value).c_str(), fast(value).c_str());
  }
  for (std::uint64_t n = 100000000000000000ull; n < 100000000000000000ull + 2000; n += 3) {
    const double value = static_cast<double>(n) + 0.5;  // integers beyond 2^53 (ties at digit 18)
    STRCMP_EQUAL(reference(value).c_str(), fast(value).c_str());
  }
}
