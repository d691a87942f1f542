// Elementary functions built from + - * / and sqrt only, so that the signal generator gives the
// same bits on every machine and C library (libm's log/sin/cos differ in the last ulp between
// implementations). Compiled with -ffp-contract=off: a fused multiply-add would change results.
// Accuracy is a few ulp, which is all the generator needs; bit-reproducibility is the point.
#pragma once

namespace stickslip::host {

// Natural logarithm of a positive, finite, normal x.
double deterministic_log(double x) noexcept;

// sin and cos of 2*pi*cycles. The argument is reduced in cycles (exact fractional part), so
// large phases such as f*t late in a long recording keep their accuracy.
struct SinCos {
  double sin;
  double cos;
};
SinCos deterministic_sincos_cycles(double cycles) noexcept;

// tan(pi * half_cycles), for the bilinear-transform pre-warp tan(pi f / fs); 0 <= half_cycles <
// 0.5.
double deterministic_tan_half_cycles(double half_cycles) noexcept;

}  // namespace stickslip::host
