#include "stickslip/host/signals/deterministic_math.hpp"

#include <cmath>

namespace stickslip::host {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;
// ln 2 split so that e * kLn2High is exact for |e| < 2^11 (kLn2High has 32 significant bits).
constexpr double kLn2High = 0.693147180369123816490;
constexpr double kLn2Low = 1.90821492927058770002e-10;
constexpr double kSqrtHalf = 0.70710678118654752440;

// sin and cos of |x| <= pi/4 by their Taylor series in Horner form: the last term kept is
// x^21/21! ~ 1e-22 at pi/4, below half an ulp.
SinCos taylor_sincos(double x) noexcept {
  // Tiny arguments: x*x would underflow (and raise the underflow flag) for no gain in accuracy.
  if (std::fabs(x) < 1e-100) return {x, 1.0};
  const double x2 = x * x;
  double s = 1.0;
  double c = 1.0;
  for (int k = 10; k >= 1; --k) {
    // sin: terms x^(2k+1)/(2k+1)!, ratio of successive terms -x^2/((2k)(2k+1)).
    s = 1.0 - x2 / static_cast<double>((2 * k) * (2 * k + 1)) * s;
    // cos: terms x^(2k)/(2k)!, ratio -x^2/((2k-1)(2k)).
    c = 1.0 - x2 / static_cast<double>((2 * k - 1) * (2 * k)) * c;
  }
  return {x * s, c};
}

}  // namespace

double deterministic_log(double x) noexcept {
  int exponent = 0;
  double mantissa = std::frexp(x, &exponent);  // exact: x = mantissa * 2^exponent, [0.5, 1)
  if (mantissa < kSqrtHalf) {
    mantissa *= 2.0;  // exact
    --exponent;
  }
  // ln(m) = 2 atanh(z), z = (m-1)/(m+1), |z| <= 0.1716; z^2 <= 0.0295, so 14 terms reach 1e-21.
  const double z = (mantissa - 1.0) / (mantissa + 1.0);
  const double z2 = z * z;
  double series = 0.0;
  for (int k = 14; k >= 1; --k) series = z2 * (1.0 / static_cast<double>(2 * k + 1) + series);
  const double ln_mantissa = 2.0 * z + 2.0 * z * series;
  const double e = static_cast<double>(exponent);
  return e * kLn2High + (e * kLn2Low + ln_mantissa);
}

SinCos deterministic_sincos_cycles(double cycles) noexcept {
  const double fraction = cycles - std::floor(cycles);      // [0, 1), exact
  const double quarter = std::floor(4.0 * fraction + 0.5);  // nearest multiple of 1/4: 0..4
  const double rest = fraction - 0.25 * quarter;            // [-1/8, 1/8] cycles, exact
  const SinCos r = taylor_sincos(kTwoPi * rest);
  switch (static_cast<int>(quarter) & 3) {
    case 1:
      return {r.cos, -r.sin};
    case 2:
      return {-r.sin, -r.cos};
    case 3:
      return {-r.cos, r.sin};
    default:
      return r;
  }
}

double deterministic_tan_half_cycles(double half_cycles) noexcept {
  const SinCos r = deterministic_sincos_cycles(0.5 * half_cycles);
  return r.sin / r.cos;
}

}  // namespace stickslip::host
