// Synthetic cab-floor accelerations a_u(t), reproducible to the bit: the same request gives the
// same file on every machine (own PRNG, Gaussian, log/sin/cos and filter design; see random.hpp,
// deterministic_math.hpp, biquad.hpp - all built with -ffp-contract=off).
//
//   wideband  Gaussian white noise band-limited to 0.5-20 Hz (4th-order Butterworth high-pass
//             and low-pass), started after a warm-up so that no filter transient shows.
//   lorry     a low-intensity cab-floor-like signal: broadband noise shaped around 1-3 Hz plus
//             engine-order tones at 6.3 and 12.6 Hz whose amplitudes drift slowly (noise
//             low-passed at 0.1 Hz).
//   harmonic  sin(2 pi f t).
//
// Samples are t = n dt for n = 0..round(duration/dt) (t from the integer index, never
// accumulated), scaled at the end so that the RMS over all written samples equals the request.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace stickslip::host {

enum class SignalKind : std::uint8_t { wideband, lorry, harmonic };

const char* signal_kind_name(SignalKind kind) noexcept;
bool parse_signal_kind(const std::string& name, SignalKind& out) noexcept;

struct GeneratorSpec {
  SignalKind kind = SignalKind::wideband;
  double rms_m_per_s2 = 1.0;
  double duration_s = 10.0;
  double dt_s = 1e-3;
  std::uint64_t seed = 1;
  double frequency_hz = 0.0;  // harmonic only
};

// Band edges and tones (Hz), also used by the tests.
inline constexpr double kWidebandLowHz = 0.5;
inline constexpr double kWidebandHighHz = 20.0;
inline constexpr double kLorryToneHz[2] = {6.3, 12.6};
inline constexpr double kMaxGeneratedSamples = 2e9;

// Throws UsageError naming the option at fault (rms > 0, duration > 0, dt > 0, 1 <= duration/dt
// <= 2e9, harmonic: 0 < frequency < 0.5/dt; wideband and lorry: 20 Hz < 0.5/dt).
void validate(const GeneratorSpec& spec);

// round(duration/dt) + 1 (spec validated).
std::uint64_t sample_count(const GeneratorSpec& spec);

// Calls sink(n, t_s, a_u) for every sample in order, after two passes over the deterministic
// stream (the first measures the RMS, the second scales): constant memory for any length.
void generate(const GeneratorSpec& spec,
              const std::function<void(std::uint64_t, double, double)>& sink);

// The whole signal in memory (the same values the CSV file holds).
std::vector<double> generate_signal(const GeneratorSpec& spec);

// Writes "t,a_u" and one row per sample to `path` (atomically: nothing is left on failure).
// Returns the number of samples written.
std::uint64_t write_generated_csv(const GeneratorSpec& spec, const std::string& path);

}  // namespace stickslip::host
