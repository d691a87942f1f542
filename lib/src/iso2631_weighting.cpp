#include "stickslip/metrics/iso2631_weighting.hpp"

#include <cmath>
#include <complex>

namespace stickslip {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Parameters of ISO 2631-1 Annex A / ISO 8041 (Hz and quality factors); f5 = f6 = 0: no step.
struct Parameters {
  double f1, q1, f2, q2, f3, f4, q4, f5, q5, f6, q6;
};

Parameters parameters(ComfortWeighting weighting) noexcept {
  const double q_butterworth = 1.0 / std::sqrt(2.0);
  if (weighting == ComfortWeighting::wd) {
    return {0.4, q_butterworth, 100.0, q_butterworth, 2.0, 2.0, 0.63, 0.0, 1.0, 0.0, 1.0};
  }
  return {0.4, q_butterworth, 100.0, q_butterworth, 12.5, 12.5, 0.63, 2.37, 0.91, 3.35, 0.91};
}

// An analogue section (B2 s^2 + B1 s + B0) / (A2 s^2 + A1 s + A0).
struct AnalogueSection {
  double b2, b1, b0, a2, a1, a0;
  double prewarp_rad_per_s;  // where the bilinear transform keeps the response exact
};

int analogue_sections(ComfortWeighting weighting, AnalogueSection (&out)[kWeightingSections]) noexcept {
  const Parameters p = parameters(weighting);
  const double w1 = 2 * kPi * p.f1, w2 = 2 * kPi * p.f2, w3 = 2 * kPi * p.f3, w4 = 2 * kPi * p.f4;
  int n = 0;
  out[n++] = {1.0, 0.0, 0.0, 1.0, w1 / p.q1, w1 * w1, w1};          // high-pass
  out[n++] = {0.0, 0.0, w2 * w2, 1.0, w2 / p.q2, w2 * w2, w2};      // low-pass
  out[n++] = {0.0, 1.0 / w3, 1.0, 1.0 / (w4 * w4), 1.0 / (p.q4 * w4), 1.0, w4};  // a-v transition
  if (p.f5 > 0.0) {
    const double w5 = 2 * kPi * p.f5, w6 = 2 * kPi * p.f6;
    const double gain = (w5 / w6) * (w5 / w6);
    out[n++] = {gain / (w5 * w5), gain / (p.q5 * w5), gain, 1.0 / (w6 * w6), 1.0 / (p.q6 * w6), 1.0,
                std::sqrt(w5 * w6)};  // upward step, pre-warped between its two corners
  }
  return n;
}

std::complex<double> evaluate(const AnalogueSection& s, std::complex<double> x) noexcept {
  return (s.b2 * x * x + s.b1 * x + s.b0) / (s.a2 * x * x + s.a1 * x + s.a0);
}

}  // namespace

const char* comfort_weighting_name(ComfortWeighting weighting) noexcept {
  return weighting == ComfortWeighting::wd ? "Wd" : "Wk";
}

double analogue_weighting_magnitude(ComfortWeighting weighting, double frequency_hz) noexcept {
  AnalogueSection sections[kWeightingSections];
  const int n = analogue_sections(weighting, sections);
  const std::complex<double> s(0.0, 2 * kPi * frequency_hz);
  std::complex<double> h(1.0, 0.0);
  for (int i = 0; i < n; ++i) h *= evaluate(sections[i], s);
  return std::abs(h);
}

ConfigResult design_weighting(ComfortWeighting weighting, double sample_rate_hz,
                              BiquadCoefficients (&sections)[kWeightingSections]) noexcept {
  ConfigResult result;
  for (auto& s : sections) s = BiquadCoefficients{};
  if (!std::isfinite(sample_rate_hz)) {
    result.status = Status::not_finite;
    result.message.append("sample_rate_hz must be finite");
    return result;
  }
  if (!(sample_rate_hz >= 2.0)) {
    result.status = Status::out_of_range;
    result.message.append("sample_rate_hz = ").append(sample_rate_hz).append(
        " is below 2 Hz: the ISO 2631-1 weighting band starts at 0.4 Hz");
    return result;
  }
  AnalogueSection analogue[kWeightingSections];
  const int n = analogue_sections(weighting, analogue);
  const double t = 1.0 / sample_rate_hz;
  int used = 0;
  for (int i = 0; i < n; ++i) {
    const AnalogueSection& a = analogue[i];
    const double w = a.prewarp_rad_per_s;
    // A corner this close to Nyquist has no meaning in the sampled signal (see the header).
    if (w / (2 * kPi) > 0.4 * sample_rate_hz) continue;
    const double k = w / std::tan(w * t / 2);  // s = k (1 - z^-1) / (1 + z^-1)
    const double kk = k * k;
    const double n0 = a.b2 * kk + a.b1 * k + a.b0, n1 = 2 * (a.b0 - a.b2 * kk),
                 n2 = a.b2 * kk - a.b1 * k + a.b0;
    const double d0 = a.a2 * kk + a.a1 * k + a.a0, d1 = 2 * (a.a0 - a.a2 * kk),
                 d2 = a.a2 * kk - a.a1 * k + a.a0;
    sections[used++] = {n0 / d0, n1 / d0, n2 / d0, d1 / d0, d2 / d0};
  }
  return result;
}

double digital_weighting_magnitude(const BiquadCoefficients (&sections)[kWeightingSections],
                                   double sample_rate_hz, double frequency_hz) noexcept {
  const std::complex<double> z1 = std::polar(1.0, -2 * kPi * frequency_hz / sample_rate_hz);  // z^-1
  std::complex<double> h(1.0, 0.0);
  for (const BiquadCoefficients& c : sections) {
    h *= (c.b0 + c.b1 * z1 + c.b2 * z1 * z1) / (1.0 + c.a1 * z1 + c.a2 * z1 * z1);
  }
  return std::abs(h);
}

}  // namespace stickslip
