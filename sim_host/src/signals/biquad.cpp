#include "stickslip/host/signals/biquad.hpp"

#include "stickslip/host/signals/deterministic_math.hpp"

namespace stickslip::host {
namespace {

// Shared denominator of the bilinear-transformed sections, with K = tan(pi f dt) (pre-warped).
struct Denominator {
  double k, norm, a1, a2;
};

Denominator denominator(double frequency_hz, double quality, double dt_s) noexcept {
  const double k = deterministic_tan_half_cycles(frequency_hz * dt_s);
  const double k2 = k * k;
  const double norm = 1.0 / (1.0 + k / quality + k2);
  return {k, norm, 2.0 * (k2 - 1.0) * norm, (1.0 - k / quality + k2) * norm};
}

}  // namespace

Biquad design_lowpass(double frequency_hz, double quality, double dt_s) noexcept {
  const Denominator d = denominator(frequency_hz, quality, dt_s);
  Biquad f;
  f.b0 = d.k * d.k * d.norm;
  f.b1 = 2.0 * f.b0;
  f.b2 = f.b0;
  f.a1 = d.a1;
  f.a2 = d.a2;
  return f;
}

Biquad design_highpass(double frequency_hz, double quality, double dt_s) noexcept {
  const Denominator d = denominator(frequency_hz, quality, dt_s);
  Biquad f;
  f.b0 = d.norm;
  f.b1 = -2.0 * f.b0;
  f.b2 = f.b0;
  f.a1 = d.a1;
  f.a2 = d.a2;
  return f;
}

Biquad design_bandpass(double frequency_hz, double quality, double dt_s) noexcept {
  const Denominator d = denominator(frequency_hz, quality, dt_s);
  Biquad f;
  f.b0 = d.k / quality * d.norm;
  f.b1 = 0.0;
  f.b2 = -f.b0;
  f.a1 = d.a1;
  f.a2 = d.a2;
  return f;
}

double butterworth_quality(int order, int section) noexcept {
  // cos(pi (2k+1) / (2 order)) = cos(2 pi * (2k+1) / (4 order))
  const double cycles = static_cast<double>(2 * section + 1) / static_cast<double>(4 * order);
  return 1.0 / (2.0 * deterministic_sincos_cycles(cycles).cos);
}

void add_butterworth_lowpass(BiquadCascade& cascade, int order, double frequency_hz,
                             double dt_s) noexcept {
  for (int section = 0; section < order / 2; ++section)
    cascade.add(design_lowpass(frequency_hz, butterworth_quality(order, section), dt_s));
}

void add_butterworth_highpass(BiquadCascade& cascade, int order, double frequency_hz,
                              double dt_s) noexcept {
  for (int section = 0; section < order / 2; ++section)
    cascade.add(design_highpass(frequency_hz, butterworth_quality(order, section), dt_s));
}

}  // namespace stickslip::host
