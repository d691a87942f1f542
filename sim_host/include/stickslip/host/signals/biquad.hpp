// Second-order IIR sections for the signal generator, designed by the bilinear transform with
// frequency pre-warping (the RBJ "Audio EQ Cookbook" forms). Design uses deterministic_math only,
// so the coefficients - and the filtered signal - are the same bits on every machine.
#pragma once

#include <array>
#include <cstddef>

namespace stickslip::host {

// Transposed direct form II: y = b0 x + z1; z1 = b1 x - a1 y + z2; z2 = b2 x - a2 y.
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
  double z1 = 0.0, z2 = 0.0;

  double process(double x) noexcept {
    const double y = b0 * x + z1;
    z1 = b1 * x - a1 * y + z2;
    z2 = b2 * x - a2 * y;
    return y;
  }
};

// Preconditions (checked by the caller): 0 < frequency_hz < 0.5 / dt_s, quality > 0.
Biquad design_lowpass(double frequency_hz, double quality, double dt_s) noexcept;
Biquad design_highpass(double frequency_hz, double quality, double dt_s) noexcept;
// Band-pass with unit gain at its centre frequency.
Biquad design_bandpass(double frequency_hz, double quality, double dt_s) noexcept;

// Q of section `section` (0-based) of an even-order Butterworth filter: 1 / (2 cos theta_k),
// theta_k = pi (2k+1) / (2 order).
double butterworth_quality(int order, int section) noexcept;

// Up to four sections in series (8th order), no heap.
class BiquadCascade {
 public:
  static constexpr std::size_t kMaxSections = 4;
  void add(const Biquad& section) noexcept {
    if (count_ < kMaxSections) sections_[count_++] = section;
  }
  double process(double x) noexcept {
    for (std::size_t i = 0; i < count_; ++i) x = sections_[i].process(x);
    return x;
  }

 private:
  std::array<Biquad, kMaxSections> sections_{};
  std::size_t count_ = 0;
};

// Appends a Butterworth low-pass / high-pass of even `order` (2 or 4 sections max in total).
void add_butterworth_lowpass(BiquadCascade& cascade, int order, double frequency_hz,
                             double dt_s) noexcept;
void add_butterworth_highpass(BiquadCascade& cascade, int order, double frequency_hz,
                              double dt_s) noexcept;

}  // namespace stickslip::host
