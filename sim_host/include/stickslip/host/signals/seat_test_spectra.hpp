// Excitations defined by a target PSD: the standard seat-test input spectra (ISO 7096 EM1-EM9,
// EN 13490 IT1/IT4, ISO 5007 AG2/AG3; docs/reference/seat-test-spectra.md) and band-limited white
// noise, synthesised as Gaussian time signals.
//
// Method: Gaussian white noise (random.hpp) through the spectrum's own filter sections, each
// discretised by the bilinear transform pre-warped at its corner (biquad.hpp), after a warm-up
// that lets every transient die. By default the noise has the one-sided PSD gmax, so the signal
// has the standard's own PSD (and about its RMS, sqrt(integral of G to 0.5/dt), up to the
// realisation's scatter); with --rms the samples are scaled so that their RMS equals the request.
// Like signal_generator, everything is + - * / sqrt and deterministic_math, compiled with
// -ffp-contract=off: the same options give the same bits on every machine.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace stickslip::host {

enum class SectionKind : std::uint8_t { highpass, lowpass, lowpass_first_order };

struct FilterSection {
  SectionKind kind;
  double frequency_hz;
  double quality;  // unused for first-order sections
};

// Up to 16 sections (B8 high-pass and low-pass), no heap: the table is a static object.
class FilterSections {
 public:
  static constexpr std::size_t kMaxSections = 16;
  void push_back(const FilterSection& section) {
    if (count_ < kMaxSections) items_[count_++] = section;
  }
  const FilterSection* begin() const noexcept { return items_.data(); }
  const FilterSection* end() const noexcept { return items_.data() + count_; }
  std::size_t size() const noexcept { return count_; }

 private:
  std::array<FilterSection, kMaxSections> items_{};
  std::size_t count_ = 0;
};

struct TargetSpectrum {
  std::string name;      // "EM6", "white" (short: no heap)
  std::string standard;  // "ISO 7096", ...; empty for white noise
  double gmax = 0.0;     // (m/s^2)^2/Hz, scale factor of G = gmax |H|^2
  FilterSections sections;
  double table_peak_hz = 0.0;  // the reference table's check columns (0 for white)
  double table_rms_0_50 = 0.0;
};

// The table, in the order of docs/reference/seat-test-spectra.md.
const std::array<TargetSpectrum, 13>& seat_test_spectra();

// The class called `name` (case-insensitive: "em6", "EM6"), or nullptr.
const TargetSpectrum* find_seat_test_spectrum(const std::string& name);

// Band-limited white noise: flat one-sided PSD gmax between the corners of 8th-order
// Butterworth high- and low-pass filters (low_hz = 0: no high-pass).
TargetSpectrum white_noise_spectrum(double low_hz, double high_hz, double gmax);

// G(f) of the analog target, (m/s^2)^2/Hz.
double target_psd(const TargetSpectrum& spectrum, double frequency_hz) noexcept;

// sqrt(integral of G over [0, upper_hz]) (composite Simpson, 1 mHz steps or finer).
double target_rms(const TargetSpectrum& spectrum, double upper_hz) noexcept;

// Frequency of the maximum of G over (0, upper_hz] (grid search on 1 mHz, then golden section).
double target_peak_hz(const TargetSpectrum& spectrum, double upper_hz) noexcept;

struct SpectrumSignalSpec {
  TargetSpectrum spectrum;
  double rms_m_per_s2 = 0.0;  // 0: the spectrum's own level up to 0.5/dt
  double duration_s = 10.0;
  double dt_s = 1e-3;
  std::uint64_t seed = 1;
};

// Throws UsageError naming the option at fault (duration, dt, rms >= 0, every corner below
// 0.45/dt, at most 2e9 samples).
void validate(const SpectrumSignalSpec& spec);

// The RMS requested, or by default that of the target PSD up to 0.5/dt (the expected value).
double requested_rms(const SpectrumSignalSpec& spec);

// Samples a_u[n] at t = n dt, n = 0..round(duration/dt).
std::vector<double> generate_spectrum_signal(const SpectrumSignalSpec& spec);

// "t,a_u" CSV, atomically. Returns the number of rows.
std::uint64_t write_spectrum_csv(const SpectrumSignalSpec& spec, const std::string& path);

// Names the generate command accepts besides wideband/lorry/harmonic: every class and "white".
std::string spectrum_kind_names();

}  // namespace stickslip::host
