#include "stickslip/metrics/iso2631_weighting.hpp"

#include <cmath>
#include <complex>
#include <utility>

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

int analogue_sections(ComfortWeighting weighting,
                      AnalogueSection (&out)[kWeightingSections]) noexcept {
  const Parameters p = parameters(weighting);
  const double w1 = 2 * kPi * p.f1, w2 = 2 * kPi * p.f2, w3 = 2 * kPi * p.f3, w4 = 2 * kPi * p.f4;
  int n = 0;
  out[n++] = {1.0, 0.0, 0.0, 1.0, w1 / p.q1, w1 * w1, w1};                       // high-pass
  out[n++] = {0.0, 0.0, w2 * w2, 1.0, w2 / p.q2, w2 * w2, w2};                   // low-pass
  out[n++] = {0.0, 1.0 / w3, 1.0, 1.0 / (w4 * w4), 1.0 / (p.q4 * w4), 1.0, w4};  // a-v transition
  if (p.f5 > 0.0) {
    const double w5 = 2 * kPi * p.f5, w6 = 2 * kPi * p.f6;
    const double gain = (w5 / w6) * (w5 / w6);
    out[n++] = {gain / (w5 * w5),  gain / (p.q5 * w5), gain,
                1.0 / (w6 * w6),   1.0 / (p.q6 * w6),  1.0,
                std::sqrt(w5 * w6)};  // upward step, pre-warped between its two corners
  }
  return n;
}

std::complex<double> evaluate(const AnalogueSection& s, std::complex<double> x) noexcept {
  return (s.b2 * x * x + s.b1 * x + s.b0) / (s.a2 * x * x + s.a1 * x + s.a0);
}

// |H(j w)|^2 of an analogue section.
double analogue_power(const AnalogueSection& s, double w_rad_per_s) noexcept {
  return std::norm(evaluate(s, std::complex<double>(0.0, w_rad_per_s)));
}

// Power response of a biquad at digital frequency w (rad/sample) in Vicanek's form: with
// phi0 = cos^2(w/2), phi1 = sin^2(w/2), phi2 = 4 phi0 phi1 the power of b0 + b1 z^-1 + b2 z^-2 is
// B0 phi0 + B1 phi1 + B2 phi2, B0 = (b0+b1+b2)^2, B1 = (b0-b1+b2)^2, B2 = -4 b0 b2; the same
// for the denominator.
struct Phi {
  double p0, p1, p2;
};
Phi phi(double w) noexcept {
  const double p1 = std::sin(w / 2) * std::sin(w / 2);
  return {1 - p1, p1, 4 * (1 - p1) * p1};
}
struct PowerCoefficients {
  double c0, c1, c2;
  double at(const Phi& f) const noexcept { return c0 * f.p0 + c1 * f.p1 + c2 * f.p2; }
};

// b0, b1, b2 from the power coefficients (false if no real numerator has that power response).
bool numerator_from_power(const PowerCoefficients& b, BiquadCoefficients& c) noexcept {
  if (!(b.c0 >= 0.0) || !(b.c1 >= 0.0)) return false;
  const double r0 = std::sqrt(b.c0), r1 = std::sqrt(b.c1);
  const double w = (r0 + r1) / 2;
  double disc = w * w + b.c2;
  // A double zero (the high-pass's at DC) puts disc at 0, where rounding may leave it just below.
  if (!(disc >= -1e-9 * w * w)) return false;
  disc = disc > 0.0 ? disc : 0.0;
  c.b0 = (w + std::sqrt(disc)) / 2;
  c.b1 = (r0 - r1) / 2;
  c.b2 = w - c.b0;
  return true;
}

// Poles mapped exactly, z = e^{pT}: no frequency warping (M. Vicanek, "Matched second order
// digital filters", 2016). The numerator first matches the analogue power at DC, at the section's
// characteristic frequency and at Nyquist; design_weighting() then refines it.
BiquadCoefficients matched_section(const AnalogueSection& s, double t) noexcept {
  BiquadCoefficients c;
  if (s.a2 == 0.0) {
    c.a1 = -std::exp(-s.a0 / s.a1 * t);
    c.a2 = 0.0;
  } else {
    const double b = s.a1 / s.a2, k = s.a0 / s.a2;  // s^2 + b s + k
    const double disc = b * b / 4 - k;
    if (disc < 0.0) {
      const double r = std::exp(-b / 2 * t), wd = std::sqrt(-disc);
      c.a1 = -2 * r * std::cos(wd * t);
      c.a2 = r * r;
    } else {
      const double root = std::sqrt(disc);
      const double z1 = std::exp((-b / 2 + root) * t), z2 = std::exp((-b / 2 - root) * t);
      c.a1 = -(z1 + z2);
      c.a2 = z1 * z2;
    }
  }
  const PowerCoefficients a{(1 + c.a1 + c.a2) * (1 + c.a1 + c.a2),
                            (1 - c.a1 + c.a2) * (1 - c.a1 + c.a2), -4 * c.a2};
  double wm = s.prewarp_rad_per_s * t;
  if (!(wm < 0.9 * kPi)) wm = kPi / 2;
  const Phi m = phi(wm);
  PowerCoefficients b{};
  b.c0 = analogue_power(s, 0.0) * a.c0;
  b.c1 = analogue_power(s, kPi / t) * a.c1;
  b.c2 = (analogue_power(s, wm / t) * a.at(m) - b.c0 * m.p0 - b.c1 * m.p1) / m.p2;
  numerator_from_power(b, c);
  return c;
}

double section_power(const BiquadCoefficients& c, const Phi& f) noexcept {
  const PowerCoefficients b{(c.b0 + c.b1 + c.b2) * (c.b0 + c.b1 + c.b2),
                            (c.b0 - c.b1 + c.b2) * (c.b0 - c.b1 + c.b2), -4 * c.b0 * c.b2};
  const PowerCoefficients a{(1 + c.a1 + c.a2) * (1 + c.a1 + c.a2),
                            (1 - c.a1 + c.a2) * (1 - c.a1 + c.a2), -4 * c.a2};
  return b.at(f) / a.at(f);
}

// Solves the n x n (n <= 3) system m x = r by Gaussian elimination with partial pivoting.
bool solve(double (&m)[3][3], double (&r)[3], int n, double (&x)[3]) noexcept {
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int row = col + 1; row < n; ++row)
      if (std::fabs(m[row][col]) > std::fabs(m[pivot][col])) pivot = row;
    if (!(std::fabs(m[pivot][col]) > 0.0)) return false;
    for (int k = 0; k < n; ++k) std::swap(m[col][k], m[pivot][k]);
    std::swap(r[col], r[pivot]);
    for (int row = col + 1; row < n; ++row) {
      const double f = m[row][col] / m[col][col];
      for (int k = col; k < n; ++k) m[row][k] -= f * m[col][k];
      r[row] -= f * r[col];
    }
  }
  for (int row = n - 1; row >= 0; --row) {
    double v = r[row];
    for (int k = row + 1; k < n; ++k) v -= m[row][k] * x[k];
    x[row] = v / m[row][row];
  }
  return true;
}

// Refines the numerators of the cascade (poles fixed) so that its power response follows the
// analogue weighting's over the band in the least-squares sense of the relative error: section by
// section, each fitted to what the others leave (a linear problem in B0, B1, B2), a few sweeps.
// Where the sample rate is well above the band this changes little; near Nyquist (200 Hz for
// the 80 Hz band) it spreads the error that three matched points would leave at the band's top.
void refine_numerators(ComfortWeighting weighting, const AnalogueSection* analogue, int n, double t,
                       BiquadCoefficients (&sections)[kWeightingSections]) noexcept {
  constexpr int kGrid = 64;
  const double nyquist_hz = 0.5 / t;
  const double low_hz = 0.2, high_hz = std::fmin(100.0, 0.92 * nyquist_hz);
  Phi grid[kGrid];
  double target[kGrid];
  for (int i = 0; i < kGrid; ++i) {
    const double f = low_hz * std::pow(high_hz / low_hz, double(i) / (kGrid - 1));
    grid[i] = phi(2 * kPi * f * t);
    const double magnitude = analogue_weighting_magnitude(weighting, f);
    target[i] = magnitude * magnitude;
  }
  // The cascade's largest |log power error| over the grid: a refinement step is kept only if it
  // lowers this, so the result is never worse than the matched design.
  const auto worst_error = [&](const BiquadCoefficients(&cascade)[kWeightingSections]) {
    double worst = 0.0;
    for (int i = 0; i < kGrid; ++i) {
      double power = 1.0;
      for (int j = 0; j < n; ++j) power *= section_power(cascade[j], grid[i]);
      const double error = std::fabs(std::log(power / target[i]));
      if (!(error <= worst)) worst = error;  // a NaN (negative power) makes it infinitely bad
      if (!(power > 0.0)) return HUGE_VAL;
    }
    return worst;
  };
  double best = worst_error(sections);
  for (int sweep = 0; sweep < 4; ++sweep) {
    for (int k = 0; k < n; ++k) {
      const BiquadCoefficients& c = sections[k];
      const PowerCoefficients a{(1 + c.a1 + c.a2) * (1 + c.a1 + c.a2),
                                (1 - c.a1 + c.a2) * (1 - c.a1 + c.a2), -4 * c.a2};
      // A zero at DC stays there (the high-pass): B0 = 0, fit B1 and B2 only.
      const bool dc_zero = analogue_power(analogue[k], 0.0) == 0.0;
      const int first = dc_zero ? 1 : 0, unknowns = 3 - first;
      double m[3][3] = {}, r[3] = {}, x[3] = {};
      for (int i = 0; i < kGrid; ++i) {
        double others = 1.0;
        for (int j = 0; j < n; ++j)
          if (j != k) others *= section_power(sections[j], grid[i]);
        const double want = target[i] / others;  // this section's power at grid point i
        const double basis[3] = {grid[i].p0, grid[i].p1, grid[i].p2};
        // Relative residual: (B . phi / A(phi) - want) / want.
        const double scale = 1.0 / (a.at(grid[i]) * want);
        for (int p = 0; p < unknowns; ++p) {
          const double bp = basis[p + first] * scale;
          r[p] += bp * 1.0;
          for (int q = 0; q < unknowns; ++q) m[p][q] += bp * basis[q + first] * scale;
        }
      }
      // Column equilibration: the basis functions differ by orders of magnitude at low frequency.
      double norm[3] = {1.0, 1.0, 1.0};
      for (int p = 0; p < unknowns; ++p)
        norm[p] = std::sqrt(m[p][p]) > 0.0 ? std::sqrt(m[p][p]) : 1.0;
      for (int p = 0; p < unknowns; ++p) {
        r[p] /= norm[p];
        for (int q = 0; q < unknowns; ++q) m[p][q] /= norm[p] * norm[q];
      }
      if (!solve(m, r, unknowns, x)) continue;
      for (int p = 0; p < unknowns; ++p) x[p] /= norm[p];
      PowerCoefficients b{};
      b.c0 = dc_zero ? 0.0 : x[0];
      b.c1 = x[1 - first];
      b.c2 = x[2 - first];
      BiquadCoefficients trial[kWeightingSections];
      for (std::size_t j = 0; j < kWeightingSections; ++j) trial[j] = sections[j];
      if (!numerator_from_power(b, trial[k])) continue;
      const double error = worst_error(trial);
      if (error < best) {
        best = error;
        sections[k] = trial[k];
      }
    }
  }
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
    result.message.append("sample_rate_hz = ")
        .append(sample_rate_hz)
        .append(" is below 2 Hz: the ISO 2631-1 weighting band starts at 0.4 Hz");
    return result;
  }
  AnalogueSection analogue[kWeightingSections];
  const int n = analogue_sections(weighting, analogue);
  const double t = 1.0 / sample_rate_hz;
  for (int i = 0; i < n; ++i) sections[i] = matched_section(analogue[i], t);
  refine_numerators(weighting, analogue, n, t, sections);
  return result;
}

double digital_weighting_magnitude(const BiquadCoefficients (&sections)[kWeightingSections],
                                   double sample_rate_hz, double frequency_hz) noexcept {
  const std::complex<double> z1 =
      std::polar(1.0, -2 * kPi * frequency_hz / sample_rate_hz);  // z^-1
  std::complex<double> h(1.0, 0.0);
  for (const BiquadCoefficients& c : sections) {
    h *= (c.b0 + c.b1 * z1 + c.b2 * z1 * z1) / (1.0 + c.a1 * z1 + c.a2 * z1 * z1);
  }
  return std::abs(h);
}

}  // namespace stickslip
