#include "stickslip/host/signals/welch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

constexpr double kPi = 3.14159265358979323846;

void fft(std::vector<std::complex<double>>& x, const std::vector<std::complex<double>>& twiddle) {
  const std::size_t n = x.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t length = 2; length <= n; length <<= 1) {
    const std::size_t stride = n / length;
    for (std::size_t start = 0; start < n; start += length) {
      for (std::size_t k = 0; k < length / 2; ++k) {
        const std::complex<double> u = x[start + k];
        const std::complex<double> v = twiddle[k * stride] * x[start + k + length / 2];
        x[start + k] = u + v;
        x[start + k + length / 2] = u - v;
      }
    }
  }
}

}  // namespace

Spectrum welch_psd(const std::vector<double>& signal, double dt_s, std::size_t segment) {
  if (segment < 8 || (segment & (segment - 1)) != 0 || segment > signal.size()) {
    throw UsageError(
        fmt::format("--segment: must be a power of two from 8 to the signal's {} "
                    "samples, got {}",
                    signal.size(), segment));
  }
  std::vector<double> window(segment);
  double window_power = 0.0;
  for (std::size_t i = 0; i < segment; ++i) {
    window[i] =
        0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(segment));
    window_power += window[i] * window[i];
  }
  std::vector<std::complex<double>> twiddle(segment / 2);
  for (std::size_t k = 0; k < segment / 2; ++k)
    twiddle[k] =
        std::polar(1.0, -2.0 * kPi * static_cast<double>(k) / static_cast<double>(segment));
  Spectrum out;
  out.psd.assign(segment / 2 + 1, 0.0);
  std::vector<std::complex<double>> buffer(segment);
  for (std::size_t start = 0; start + segment <= signal.size(); start += segment / 2) {
    double mean = 0.0;
    for (std::size_t i = 0; i < segment; ++i) mean += signal[start + i];
    mean /= static_cast<double>(segment);
    for (std::size_t i = 0; i < segment; ++i) buffer[i] = window[i] * (signal[start + i] - mean);
    fft(buffer, twiddle);
    for (std::size_t k = 0; k < out.psd.size(); ++k) out.psd[k] += std::norm(buffer[k]);
    ++out.segments;
  }
  const double scale = dt_s / (window_power * static_cast<double>(out.segments));
  out.frequency_hz.resize(out.psd.size());
  for (std::size_t k = 0; k < out.psd.size(); ++k) {
    out.psd[k] *= (k == 0 || k == segment / 2 ? 1.0 : 2.0) * scale;
    out.frequency_hz[k] = static_cast<double>(k) / (static_cast<double>(segment) * dt_s);
  }
  return out;
}

Spectrum welch_psd_over_parts(const std::vector<const std::vector<double>*>& parts, double dt_s,
                              std::size_t segment, std::size_t& short_samples) {
  if (parts.size() == 1) return welch_psd(*parts.front(), dt_s, segment);
  Spectrum total;
  std::size_t longest = 0;
  for (const std::vector<double>* part : parts) {
    longest = std::max(longest, part->size());
    if (part->size() < segment) {
      short_samples += part->size();
      continue;
    }
    const Spectrum spectrum = welch_psd(*part, dt_s, segment);
    if (total.segments == 0) {
      total.frequency_hz = spectrum.frequency_hz;
      total.psd.assign(spectrum.psd.size(), 0.0);
    }
    for (std::size_t k = 0; k < spectrum.psd.size(); ++k)
      total.psd[k] += spectrum.psd[k] * static_cast<double>(spectrum.segments);
    total.segments += spectrum.segments;
  }
  if (total.segments == 0) {
    throw UsageError(fmt::format(
        "--segment: {} samples is longer than every part between the gaps (the longest has {})",
        segment, longest));
  }
  for (double& value : total.psd) value /= static_cast<double>(total.segments);
  return total;
}

}  // namespace stickslip::host
