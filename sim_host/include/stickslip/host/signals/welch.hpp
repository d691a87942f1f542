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

// Welch over the parts of a recording cut at its gaps (--gaps split), each part's PSD weighted by
// its number of Welch segments: the average of every segment's periodogram, none across a gap.
// A part shorter than `segment` gives none; its samples are added to `short_samples`. One part:
// welch_psd() itself. UsageError when no part holds one segment.
Spectrum welch_psd_over_parts(const std::vector<const std::vector<double>*>& parts, double dt_s,
                              std::size_t segment, std::size_t& short_samples);

}  // namespace stickslip::host
