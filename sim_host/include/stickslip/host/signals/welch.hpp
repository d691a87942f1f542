// Power spectral density by Welch's method (Hann window, 50 % overlap, each segment's mean
// removed), one-sided, in units^2/Hz: what `stickslip psd` writes and the figures plot.
#pragma once

#include <cstddef>
#include <vector>

namespace stickslip::host {

struct Spectrum {
  std::vector<double> frequency_hz;  // k / (segment dt), k = 0..segment/2
  std::vector<double> psd;
  std::size_t segments = 0;
};

// `segment` is a power of two >= 8 and at most the signal's length (UsageError otherwise).
Spectrum welch_psd(const std::vector<double>& signal, double dt_s, std::size_t segment);

}  // namespace stickslip::host
