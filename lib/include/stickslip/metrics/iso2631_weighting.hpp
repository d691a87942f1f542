// ISO 2631-1 frequency weightings for whole-body vibration, as a cascade of four biquads designed
// in configure() for the sample rate: Wk (vertical, z) and Wd (horizontal, x and y).
//
// The analogue weighting (ISO 2631-1:1997 Annex A, the parameters as ISO 8041 tabulates them) is
// the product of
//   band-limiting high-pass  s^2 / (s^2 + w1 s/Q1 + w1^2)                   f1 = 0.4 Hz, Q1 =
//   1/sqrt2 band-limiting low-pass   w2^2 / (s^2 + w2 s/Q2 + w2^2)                  f2 = 100 Hz, Q2
//   = 1/sqrt2 a-v transition           (1 + s/w3) / (1 + s/(Q4 w4) + s^2/w4^2) upward step
//   (w5/w6)^2 (1 + s/(Q5 w5) + s^2/w5^2) / (1 + s/(Q6 w6) + s^2/w6^2)
// with Wk: f3 = f4 = 12.5 Hz, Q4 = 0.63, f5 = 2.37 Hz, Q5 = 0.91, f6 = 3.35 Hz, Q6 = 0.91;
//      Wd: f3 = f4 = 2 Hz, Q4 = 0.63, no upward step.
// Each section becomes a biquad with its poles mapped exactly (z = e^{pT}) and its numerator first
// matched to the section's magnitude at DC, its characteristic frequency and Nyquist (Vicanek's
// matched second-order filters), then refined by least squares on the relative error of the whole
// cascade over 0.2 Hz .. min(100 Hz, 0.92 Nyquist), keeping a change only where it lowers the
// worst error. No frequency warping: the weighting holds up to near Nyquist. Measured against the
// definition at the tabulated bands 0.5-80 Hz: within 0.31 dB at 200 Hz, 0.005 dB at 500 Hz and
// above (tests/core/test_ride_comfort.cpp).
//
// The step is one multiply-add cascade (direct form II transposed), no division, no call.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip {

enum class ComfortWeighting : std::uint8_t {
  wk,  // vertical (z) at the seat surface, ISO 2631-1 health/comfort
  wd,  // horizontal (x, y)
};

const char* comfort_weighting_name(ComfortWeighting weighting) noexcept;  // "Wk", "Wd"

// |W(j 2 pi f)| of the analogue weighting (the standard's definition; for reports and tests).
double analogue_weighting_magnitude(ComfortWeighting weighting, double frequency_hz) noexcept;

// b0 + b1 z^-1 + b2 z^-2 over 1 + a1 z^-1 + a2 z^-2.
struct BiquadCoefficients {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
};

inline constexpr std::size_t kWeightingSections = 4;

// Designs the cascade; refuses a non-finite or non-positive sample rate, or one below 2 Hz (the
// weighting's band starts at 0.4 Hz; its high-pass needs 0.4 Hz < 0.2 fs). Unused sections are
// identities.
ConfigResult design_weighting(ComfortWeighting weighting, double sample_rate_hz,
                              BiquadCoefficients (&sections)[kWeightingSections]) noexcept;

// |H(e^{j 2 pi f / fs})| of a designed cascade (for reports and tests).
double digital_weighting_magnitude(const BiquadCoefficients (&sections)[kWeightingSections],
                                   double sample_rate_hz, double frequency_hz) noexcept;

template <typename T>
class WeightingFilter {
 public:
  ConfigResult configure(ComfortWeighting weighting, double sample_rate_hz) noexcept {
    BiquadCoefficients designed[kWeightingSections];
    ConfigResult result = design_weighting(weighting, sample_rate_hz, designed);
    if (!result.ok()) return result;
    for (std::size_t i = 0; i < kWeightingSections; ++i) {
      design_[i] = designed[i];
      c_[i] = {S::from_double(designed[i].b0), S::from_double(designed[i].b1),
               S::from_double(designed[i].b2), S::from_double(designed[i].a1),
               S::from_double(designed[i].a2)};
    }
    sample_rate_hz_ = sample_rate_hz;
    reset();
    return result;
  }
  void reset() noexcept {
    for (auto& s : z_) s = {T(0), T(0)};
  }
  // One input sample in, one weighted sample out (m/s^2).
  T step(T input) noexcept {
    T x = input;
    for (std::size_t i = 0; i < kWeightingSections; ++i) {
      const Coefficients& c = c_[i];
      State& z = z_[i];
      const T y = c.b0 * x + z.z1;
      z.z1 = c.b1 * x - c.a1 * y + z.z2;
      z.z2 = c.b2 * x - c.a2 * y;
      x = y;
    }
    return x;
  }
  const BiquadCoefficients (&sections() const noexcept)[kWeightingSections] { return design_; }
  double sample_rate_hz() const noexcept { return sample_rate_hz_; }

 private:
  using S = ScalarTraits<T>;
  struct Coefficients {
    T b0, b1, b2, a1, a2;
  };
  struct State {
    T z1, z2;
  };
  Coefficients c_[kWeightingSections]{};
  State z_[kWeightingSections]{};
  BiquadCoefficients design_[kWeightingSections]{};
  double sample_rate_hz_ = 0.0;
};

}  // namespace stickslip
