#include "stickslip/host/signals/resample.hpp"

#include <fmt/format.h>
#include <soxr.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

namespace {

// Second derivatives of the natural spline (zero at both ends): the tridiagonal system of the
// knots' continuity conditions, solved by the Thomas algorithm (diagonally dominant, so stable).
std::vector<double> spline_second_derivatives(const std::vector<double>& t,
                                              const std::vector<double>& y) {
  const std::size_t n = t.size();
  std::vector<double> m(n, 0.0);
  if (n < 3) return m;
  std::vector<double> diagonal(n, 0.0), right(n, 0.0), upper(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = t[i] - t[i - 1];
    const double h1 = t[i + 1] - t[i];
    diagonal[i] = 2.0 * (h0 + h1);
    upper[i] = h1;
    right[i] = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
  }
  // Forward sweep over rows 1..n-2 (the lower coefficient of row i is h0 = t[i] - t[i-1]).
  for (std::size_t i = 2; i + 1 < n; ++i) {
    const double lower = t[i] - t[i - 1];
    const double factor = lower / diagonal[i - 1];
    diagonal[i] -= factor * upper[i - 1];
    right[i] -= factor * right[i - 1];
  }
  for (std::size_t i = n - 2; i >= 1; --i) {
    m[i] = (right[i] - upper[i] * m[i + 1]) / diagonal[i];
    if (i == 1) break;
  }
  return m;
}

// Half the support of libsoxr's SOXR_VHQ filter, in samples of the lower of the two rates, with
// margin. The filter is designed at the lower rate's Nyquist frequency (175 dB, 29 bits), so its
// length scales with that rate: measured impulse responses (50 Hz to 10 kHz into 1 kHz) fall
// below 1e-16 of the peak (1e-11 for the half-band stages of a power-of-two decimation) beyond
// 150 samples of the lower rate, as Kaiser's length (A - 8) / (2.285 dw) gives for A = 175 dB
// and a transition band of ~8 % of the lower Nyquist frequency. Padding by 256 keeps every
// output sample of the record within reach of the continuation, never of soxr's zeros.
constexpr double kFilterHalfSupport = 256.0;

// The record continued past both ends by odd (point) reflection about its end samples,
// 2 x[0] - x[-i] and 2 x[n-1] - x[2(n-1) - i], repeated for a record shorter than the padding.
// It continues value and slope, so a constant or a ramp goes through the band-limited filter
// unchanged, where soxr's own zeros would make a step at each end.
double odd_reflection(const std::vector<double>& x, std::ptrdiff_t i) {
  if (x.size() == 1) return x.front();
  const auto last = static_cast<std::ptrdiff_t>(x.size()) - 1;
  double sign = 1.0, offset = 0.0;
  while (i < 0 || i > last) {
    const bool before = i < 0;
    offset += sign * 2.0 * (before ? x.front() : x.back());
    sign = -sign;
    i = before ? -i : 2 * last - i;
  }
  return offset + sign * x[static_cast<std::size_t>(i)];
}

// The padding before the record, at least pad_min input samples, that spans a whole number of
// output steps, so that the padded record's output grid holds the record's own (k / out_rate from
// its first sample) exactly. Such a padding exists when out/in is a ratio of small integers, as
// two nominal rates are (soxr then takes it as rational too, and its grid is exact); 0 when no
// multiple up to pad_min + 4096 is one (the ratio is irrational to soxr's 32-bit clock), as for
// a logger's mean step.
std::size_t aligned_left_padding(std::size_t pad_min, double out_per_in) {
  for (std::size_t pad = pad_min; pad < pad_min + 4096; ++pad) {
    const double outputs = static_cast<double>(pad) * out_per_in;
    if (std::fabs(outputs - std::round(outputs)) <= 1e-12 * outputs) return pad;
  }
  return 0;
}

}  // namespace

std::vector<double> spline_onto_grid(const std::vector<double>& t_s,
                                     const std::vector<double>& values, double t0_s, double step_s,
                                     std::size_t count) {
  const std::vector<double> m = spline_second_derivatives(t_s, values);
  std::vector<double> out(count);
  std::size_t i = 0;  // the interval [t_s[i], t_s[i+1]] that holds the grid point
  const std::size_t last = t_s.size() - 1;
  for (std::size_t k = 0; k < count; ++k) {
    const double t = std::min(t0_s + static_cast<double>(k) * step_s, t_s[last]);
    while (i + 1 < last && t_s[i + 1] <= t) ++i;
    const double h = t_s[i + 1] - t_s[i];
    const double a = (t_s[i + 1] - t) / h;
    const double b = (t - t_s[i]) / h;
    out[k] = a * values[i] + b * values[i + 1] +
             ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6.0;
  }
  return out;
}

std::vector<double> resample_rate(const std::vector<double>& values, double in_rate_hz,
                                  double out_rate_hz, std::size_t out_count) {
  const std::size_t n = values.size();
  const double out_per_in = out_rate_hz / in_rate_hz;
  // The padding in input samples: kFilterHalfSupport samples of the lower rate.
  const auto pad_min = static_cast<std::size_t>(
      std::ceil(kFilterHalfSupport * in_rate_hz / std::min(in_rate_hz, out_rate_hz)));
  const std::size_t left = aligned_left_padding(pad_min, out_per_in);
  const bool aligned = left != 0;
  // Without an aligned padding the start is continued by its value instead: the record less its
  // first sample starts at zero, so soxr's zeros before it continue it without a step.
  const double start_value = aligned || n == 0 ? 0.0 : values.front();

  std::vector<double> padded(left + n + pad_min);
  for (std::size_t i = 0; i < padded.size(); ++i) {
    const auto index = static_cast<std::ptrdiff_t>(i) - static_cast<std::ptrdiff_t>(left);
    padded[i] = odd_reflection(values, index) - start_value;
  }
  // Output k of the padded record is at (k - first) / out_rate_hz from values[0].
  const auto first = static_cast<std::size_t>(std::llround(static_cast<double>(left) * out_per_in));

  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT64_I, SOXR_FLOAT64_I);
  const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_VHQ, 0);
  // soxr_oneshot delivers round(n out/in) samples; room for one more than that.
  const double expected = static_cast<double>(padded.size()) * out_per_in;
  std::vector<double> out(static_cast<std::size_t>(expected) + 2);
  std::size_t used = 0, made = 0;
  const soxr_error_t error =
      soxr_oneshot(in_rate_hz, out_rate_hz, 1, padded.data(), padded.size(), &used, out.data(),
                   out.size(), &made, &io, &quality, nullptr);
  if (error != nullptr) {
    throw HostError(
        fmt::format("resampling {} Hz to {} Hz: libsoxr: {}", in_rate_hz, out_rate_hz, error));
  }
  // The padding holds the samples past the record's end that the grid can ask for.
  const std::size_t available = made > first ? made - first : 0;
  std::vector<double> trimmed(std::min(available, out_count));
  for (std::size_t k = 0; k < trimmed.size(); ++k) trimmed[k] = out[first + k] + start_value;
  return trimmed;
}

std::vector<double> resample_step(const std::vector<double>& values, double step_s,
                                  double new_step_s) {
  const double span = step_s * static_cast<double>(values.size() - 1);
  const auto count = static_cast<std::size_t>(std::floor(span / new_step_s + 1e-6)) + 1;
  return resample_rate(values, 1.0 / step_s, 1.0 / new_step_s, count);
}

}  // namespace stickslip::host
