#include "stickslip/host/signals/seat_test_spectra.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/signals/biquad.hpp"
#include "stickslip/host/signals/deterministic_math.hpp"
#include "stickslip/host/signals/random.hpp"

namespace stickslip::host {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kNoiseStream = 11;  // its own stream: independent of the other kinds
constexpr double kMaxSamples = 2e9;

// Butterworth sections by order; the table's Q values (0.541, 1.306; 0.510, 0.601, 0.900, 2.563;
// 0.707) are these, rounded.
void add_butterworth(FilterSections& sections, SectionKind kind, int order, double frequency_hz) {
  for (int section = 0; section < order / 2; ++section)
    sections.push_back({kind, frequency_hz, butterworth_quality(order, section)});
}

TargetSpectrum make(const char* name, const char* standard, double gmax, int hp_order, double hp_hz,
                    int lp_order, double lp_hz, double peak_hz, double rms) {
  TargetSpectrum s;
  s.name = name;
  s.standard = standard;
  s.gmax = gmax;
  add_butterworth(s.sections, SectionKind::highpass, hp_order, hp_hz);
  if (lp_order == 1) {
    s.sections.push_back({SectionKind::lowpass_first_order, lp_hz, 0.0});
  } else {
    add_butterworth(s.sections, SectionKind::lowpass, lp_order, lp_hz);
  }
  s.table_peak_hz = peak_hz;
  s.table_rms_0_50 = rms;
  return s;
}

std::array<TargetSpectrum, 13> build_table() {
  // docs/reference/seat-test-spectra.md (HVLab hvtestspectrum.m): class, Gmax, HP order and
  // corner, LP order and corner, and the table's peak and rms for the tests.
  return {
      make("EM1", "ISO 7096", 2.82, 4, 1.5, 4, 2.5, 1.94, 1.71),
      make("EM2", "ISO 7096", 2.72, 4, 1.5, 4, 3.0, 2.12, 2.05),
      make("EM3", "ISO 7096", 1.93, 4, 1.5, 4, 3.0, 2.12, 1.73),
      make("EM4", "ISO 7096", 0.60, 4, 1.5, 4, 3.0, 2.12, 0.96),
      make("EM5", "ISO 7096", 1.11, 4, 1.5, 1, 3.5, 2.09, 2.06),
      make("EM6", "ISO 7096", 0.79, 2, 6.5, 2, 9.0, 7.65, 1.73),
      make("EM7", "ISO 7096", 9.25, 8, 3.0, 8, 3.5, 3.24, 2.25),
      make("EM8", "ISO 7096", 1.45, 4, 3.0, 2, 3.0, 3.33, 1.05),
      make("EM9", "ISO 7096", 2.10, 4, 3.5, 2, 4.0, 4.01, 1.64),
      make("IT1", "EN 13490", 1.66, 4, 4.5, 2, 5.0, 5.12, 1.59),
      make("IT4", "EN 13490", 1.64, 4, 1.5, 4, 3.0, 2.12, 1.59),
      make("AG2", "ISO 5007", 7.22, 8, 2.1, 8, 2.6, 2.34, 1.94),
      make("AG3", "ISO 5007", 5.85, 8, 1.95, 8, 2.45, 2.19, 1.74),
  };
}

// |H(j w)|^2 of one analog section, w in rad/s: rational, no libm.
double section_gain_squared(const FilterSection& s, double w) noexcept {
  const double wn = 2.0 * kPi * s.frequency_hz;
  if (s.kind == SectionKind::lowpass_first_order) return wn * wn / (w * w + wn * wn);
  const double real = wn * wn - w * w;
  const double imag = wn * w / s.quality;
  const double denominator = real * real + imag * imag;
  const double numerator = s.kind == SectionKind::highpass ? w * w * w * w : wn * wn * wn * wn;
  return numerator / denominator;
}

Biquad design_first_order_lowpass(double frequency_hz, double dt_s) noexcept {
  const double k = deterministic_tan_half_cycles(frequency_hz * dt_s);
  Biquad f;
  f.b0 = k / (1.0 + k);
  f.b1 = f.b0;
  f.b2 = 0.0;
  f.a1 = (k - 1.0) / (k + 1.0);
  f.a2 = 0.0;
  return f;
}

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

const std::array<TargetSpectrum, 13>& seat_test_spectra() {
  static const std::array<TargetSpectrum, 13> table = build_table();
  return table;
}

const TargetSpectrum* find_seat_test_spectrum(const std::string& name) {
  const std::string wanted = upper(name);
  for (const TargetSpectrum& s : seat_test_spectra())
    if (s.name == wanted) return &s;
  return nullptr;
}

TargetSpectrum white_noise_spectrum(double low_hz, double high_hz, double gmax) {
  TargetSpectrum s;
  s.name = "white";
  s.gmax = gmax;
  if (low_hz > 0.0) add_butterworth(s.sections, SectionKind::highpass, 8, low_hz);
  add_butterworth(s.sections, SectionKind::lowpass, 8, high_hz);
  return s;
}

double target_psd(const TargetSpectrum& spectrum, double frequency_hz) noexcept {
  const double w = 2.0 * kPi * frequency_hz;
  double gain = spectrum.gmax;
  for (const FilterSection& s : spectrum.sections) gain *= section_gain_squared(s, w);
  return gain;
}

double target_rms(const TargetSpectrum& spectrum, double upper_hz) noexcept {
  if (!(upper_hz > 0.0)) return 0.0;
  auto intervals = static_cast<long long>(std::ceil(upper_hz / 1e-3));
  if (intervals % 2 != 0) ++intervals;
  const double h = upper_hz / static_cast<double>(intervals);
  double sum = target_psd(spectrum, 0.0) + target_psd(spectrum, upper_hz);
  for (long long i = 1; i < intervals; ++i)
    sum += (i % 2 != 0 ? 4.0 : 2.0) * target_psd(spectrum, h * static_cast<double>(i));
  return std::sqrt(sum * h / 3.0);
}

double target_peak_hz(const TargetSpectrum& spectrum, double upper_hz) noexcept {
  const double step = 1e-3;
  double best_f = step, best = 0.0;
  for (double f = step; f <= upper_hz; f += step) {
    const double g = target_psd(spectrum, f);
    if (g > best) {
      best = g;
      best_f = f;
    }
  }
  double a = best_f - step, b = best_f + step;
  const double ratio = 0.6180339887498949;
  for (int i = 0; i < 60; ++i) {
    const double c = b - ratio * (b - a), d = a + ratio * (b - a);
    if (target_psd(spectrum, c) > target_psd(spectrum, d))
      b = d;
    else
      a = c;
  }
  return 0.5 * (a + b);
}

void validate(const SpectrumSignalSpec& spec) {
  const auto positive = [](const char* option, double value) {
    if (!std::isfinite(value) || !(value > 0.0))
      throw UsageError(fmt::format("{}: must be a finite number > 0, got {}", option, value));
  };
  positive("--duration", spec.duration_s);
  positive("--dt", spec.dt_s);
  if (!std::isfinite(spec.rms_m_per_s2) || spec.rms_m_per_s2 < 0.0)
    throw UsageError(fmt::format("--rms: must be a finite number >= 0, got {}", spec.rms_m_per_s2));
  const double steps = spec.duration_s / spec.dt_s;
  if (!(steps <= kMaxSamples) || std::llround(steps) < 1)
    throw UsageError(fmt::format("--duration/--dt: {} samples (need 1 to {})", steps, kMaxSamples));
  for (const FilterSection& s : spec.spectrum.sections) {
    if (!std::isfinite(s.frequency_hz) || !(s.frequency_hz > 0.0) ||
        !(s.frequency_hz < 0.45 / spec.dt_s)) {
      throw UsageError(
          fmt::format("--dt: {} has a corner at {} Hz, which needs 0 < f < 0.45/dt = {} Hz",
                      spec.spectrum.name, s.frequency_hz, 0.45 / spec.dt_s));
    }
  }
}

double requested_rms(const SpectrumSignalSpec& spec) {
  return spec.rms_m_per_s2 > 0.0 ? spec.rms_m_per_s2 : target_rms(spec.spectrum, 0.5 / spec.dt_s);
}

namespace {

// The unscaled signal, sample by sample (n = 0, 1, ...), after the warm-up.
class SpectrumStream {
 public:
  explicit SpectrumStream(const SpectrumSignalSpec& spec) : noise_(spec.seed, kNoiseStream) {
    const double dt = spec.dt_s;
    double lowest_hz = 0.5 / dt;
    for (const FilterSection& s : spec.spectrum.sections) {
      lowest_hz = std::fmin(lowest_hz, s.frequency_hz);
      switch (s.kind) {
        case SectionKind::highpass:
          filter_[count_++] = design_highpass(s.frequency_hz, s.quality, dt);
          break;
        case SectionKind::lowpass:
          filter_[count_++] = design_lowpass(s.frequency_hz, s.quality, dt);
          break;
        case SectionKind::lowpass_first_order:
          filter_[count_++] = design_first_order_lowpass(s.frequency_hz, dt);
          break;
      }
    }
    // Warm-up: the slowest pole (about the lowest corner, Q up to 2.6) decays to 1e-16 well
    // within 30 s + 40 cycles of the lowest corner.
    const auto warm_up = static_cast<std::uint64_t>(std::llround((30.0 + 40.0 / lowest_hz) / dt));
    for (std::uint64_t n = 0; n < warm_up; ++n) next();
  }
  double next() noexcept {
    double x = noise_.next();
    for (std::size_t i = 0; i < count_; ++i) x = filter_[i].process(x);
    return x;
  }

 private:
  GaussianSource noise_;
  std::array<Biquad, FilterSections::kMaxSections> filter_{};
  std::size_t count_ = 0;
};

// The factor applied to the stream: to the requested RMS (a first pass over the same stream
// measures it; Neumaier-compensated double sum, not long double, whose width differs between
// machines), or to the standard's level: white noise of one-sided PSD 2 sigma^2 dt = gmax, so
// that the filtered signal's PSD is gmax |H|^2 in expectation at every frequency. (Scaling to the
// analog RMS instead would lift the whole band by the tail power the bilinear transform removes
// near Nyquist: +11 % for EM6 at dt = 10 ms.)
double stream_scale(const SpectrumSignalSpec& spec, std::uint64_t count) {
  if (!(spec.rms_m_per_s2 > 0.0)) return std::sqrt(spec.spectrum.gmax / (2.0 * spec.dt_s));
  SpectrumStream stream(spec);
  double sum = 0.0, compensation = 0.0;
  for (std::uint64_t n = 0; n < count; ++n) {
    const double value = stream.next();
    const double term = value * value;
    const double total = sum + term;
    compensation += std::fabs(sum) >= std::fabs(term) ? (sum - total) + term : (term - total) + sum;
    sum = total;
  }
  const double raw_rms = std::sqrt((sum + compensation) / static_cast<double>(count));
  if (!(raw_rms > 0.0)) throw UsageError(spec.spectrum.name + ": the signal is identically zero");
  return spec.rms_m_per_s2 / raw_rms;
}

std::uint64_t spectrum_sample_count(const SpectrumSignalSpec& spec) {
  return static_cast<std::uint64_t>(std::llround(spec.duration_s / spec.dt_s)) + 1;
}

}  // namespace

std::vector<double> generate_spectrum_signal(const SpectrumSignalSpec& spec) {
  validate(spec);
  const std::uint64_t count = spectrum_sample_count(spec);
  const double scale = stream_scale(spec, count);
  SpectrumStream stream(spec);
  std::vector<double> out(static_cast<std::size_t>(count));
  for (double& value : out) value = scale * stream.next();
  return out;
}

// Streams: constant memory for any length (two passes with --rms).
std::uint64_t write_spectrum_csv(const SpectrumSignalSpec& spec, const std::string& path) {
  validate(spec);
  const std::uint64_t count = spectrum_sample_count(spec);
  const double scale = stream_scale(spec, count);
  AtomicOutputFile file(path);
  CsvWriter writer(file);
  writer.text("t,a_u\n");
  SpectrumStream stream(spec);
  for (std::uint64_t n = 0; n < count; ++n) {
    writer.number(static_cast<double>(n) * spec.dt_s);
    writer.separator();
    writer.number(scale * stream.next());
    writer.end_row();
  }
  writer.flush();
  file.commit();
  return count;
}

std::string spectrum_kind_names() {
  std::string names;
  for (const TargetSpectrum& s : seat_test_spectra()) names += s.name + ", ";
  return names + "white";
}

}  // namespace stickslip::host
