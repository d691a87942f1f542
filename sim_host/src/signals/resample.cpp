#include "stickslip/host/signals/resample.hpp"

#include <fmt/format.h>
#include <soxr.h>

#include <algorithm>
#include <cmath>

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
  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT64_I, SOXR_FLOAT64_I);
  const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_VHQ, 0);
  // soxr_oneshot delivers round(n out/in) samples; room for one more than that.
  const double expected = static_cast<double>(values.size()) * out_rate_hz / in_rate_hz;
  std::vector<double> out(static_cast<std::size_t>(expected) + 2);
  std::size_t used = 0, made = 0;
  const soxr_error_t error =
      soxr_oneshot(in_rate_hz, out_rate_hz, 1, values.data(), values.size(), &used, out.data(),
                   out.size(), &made, &io, &quality, nullptr);
  if (error != nullptr) {
    throw HostError(
        fmt::format("resampling {} Hz to {} Hz: libsoxr: {}", in_rate_hz, out_rate_hz, error));
  }
  out.resize(std::min(made, out_count));
  return out;
}

std::vector<double> resample_step(const std::vector<double>& values, double step_s,
                                  double new_step_s) {
  const double span = step_s * static_cast<double>(values.size() - 1);
  const auto count = static_cast<std::size_t>(std::floor(span / new_step_s + 1e-6)) + 1;
  return resample_rate(values, 1.0 / step_s, 1.0 / new_step_s, count);
}

}  // namespace stickslip::host
