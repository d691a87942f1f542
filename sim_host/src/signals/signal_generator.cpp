#include "stickslip/host/signals/signal_generator.hpp"

#include <fmt/format.h>

#include <cmath>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/signals/biquad.hpp"
#include "stickslip/host/signals/deterministic_math.hpp"
#include "stickslip/host/signals/random.hpp"

namespace stickslip::host {
namespace {

// Independent random streams of one seed, one per signal component.
enum Stream : std::uint64_t { kMainNoise = 1, kModulation1 = 2, kModulation2 = 3, kPhases = 4 };

// Warm-up before sample 0, long enough for every filter transient to die out (slowest pole of
// the 0.5 Hz high-pass decays at ~1.2 1/s, that of the 0.1 Hz modulation low-pass at ~0.44 1/s).
constexpr double kWidebandWarmUpS = 30.0;
constexpr double kLorryWarmUpS = 60.0;

// Lorry: broadband part, two band-passes at 2 Hz (-3 dB near 1.3 and 3 Hz together).
constexpr double kLorryBandHz = 2.0;
constexpr double kLorryBandQuality = 0.7;
constexpr double kLorryToneAmplitude[2] = {0.8, 0.5};  // against a unit-RMS broadband part
constexpr double kModulationHz = 0.1;
constexpr double kModulationDepth = 0.3;  // amplitude varies as 1 + depth * (unit-RMS noise)

// RMS of the cascade's response to unit white noise: sqrt(sum of its squared impulse response),
// over `seconds` (long enough for the response to fall below 1e-15 of its peak).
double noise_gain(BiquadCascade cascade, double seconds, double dt_s) {
  const auto count = static_cast<std::uint64_t>(std::llround(seconds / dt_s));
  double energy = 0.0;
  for (std::uint64_t n = 0; n < count; ++n) {
    const double y = cascade.process(n == 0 ? 1.0 : 0.0);
    energy += y * y;
  }
  return std::sqrt(energy);
}

// The unscaled signal as a stream: next() returns sample n = 0, 1, 2, ... in order.
class SignalStream {
 public:
  explicit SignalStream(const GeneratorSpec& spec)
      : spec_(spec),
        noise_(spec.seed, kMainNoise),
        modulation_noise_{GaussianSource(spec.seed, kModulation1),
                          GaussianSource(spec.seed, kModulation2)} {
    const double dt = spec.dt_s;
    double warm_up_s = 0.0;
    switch (spec.kind) {
      case SignalKind::wideband:
        add_butterworth_highpass(filter_, 4, kWidebandLowHz, dt);
        add_butterworth_lowpass(filter_, 4, kWidebandHighHz, dt);
        warm_up_s = kWidebandWarmUpS;
        break;
      case SignalKind::lorry: {
        filter_.add(design_bandpass(kLorryBandHz, kLorryBandQuality, dt));
        filter_.add(design_bandpass(kLorryBandHz, kLorryBandQuality, dt));
        broadband_scale_ = 1.0 / noise_gain(filter_, 10.0, dt);
        for (BiquadCascade& envelope : modulation_filter_) {
          add_butterworth_lowpass(envelope, 2, kModulationHz, dt);
        }
        modulation_scale_ = 1.0 / noise_gain(modulation_filter_[0], 100.0, dt);
        Xoshiro256StarStar phases(spec.seed, kPhases);
        for (double& phase : tone_phase_cycles_) phase = phases.uniform();
        warm_up_s = kLorryWarmUpS;
        break;
      }
      case SignalKind::harmonic:
        break;
    }
    const auto warm_up = static_cast<std::uint64_t>(std::llround(warm_up_s / dt));
    for (std::uint64_t n = 0; n < warm_up; ++n) filtered_noise();
  }

  double next() {
    const double t = static_cast<double>(index_++) * spec_.dt_s;
    switch (spec_.kind) {
      case SignalKind::wideband:
        return filtered_noise().broadband;
      case SignalKind::lorry: {
        const Filtered f = filtered_noise();
        double value = broadband_scale_ * f.broadband;
        for (int k = 0; k < 2; ++k) {
          const double amplitude = kLorryToneAmplitude[k] *
                                   (1.0 + kModulationDepth * modulation_scale_ * f.modulation[k]);
          value += amplitude *
                   deterministic_sincos_cycles(kLorryToneHz[k] * t + tone_phase_cycles_[k]).cos;
        }
        return value;
      }
      case SignalKind::harmonic:
        break;
    }
    return deterministic_sincos_cycles(spec_.frequency_hz * t).sin;
  }

 private:
  struct Filtered {
    double broadband;
    double modulation[2];
  };

  // One step of every noise filter (also used for the warm-up).
  Filtered filtered_noise() {
    Filtered f{0.0, {0.0, 0.0}};
    if (spec_.kind == SignalKind::harmonic) return f;
    f.broadband = filter_.process(noise_.next());
    if (spec_.kind == SignalKind::lorry) {
      for (int k = 0; k < 2; ++k)
        f.modulation[k] = modulation_filter_[k].process(modulation_noise_[k].next());
    }
    return f;
  }

  GeneratorSpec spec_;
  GaussianSource noise_;
  GaussianSource modulation_noise_[2];
  BiquadCascade filter_;
  BiquadCascade modulation_filter_[2];
  double broadband_scale_ = 1.0;
  double modulation_scale_ = 1.0;
  double tone_phase_cycles_[2] = {0.0, 0.0};
  std::uint64_t index_ = 0;
};

// Neumaier-compensated sum: the RMS must hit the request to ~1e-16 over 1e9 samples.
class CompensatedSum {
 public:
  void add(double value) noexcept {
    const double total = sum_ + value;
    compensation_ +=
        std::fabs(sum_) >= std::fabs(value) ? (sum_ - total) + value : (value - total) + sum_;
    sum_ = total;
  }
  double value() const noexcept { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

std::string number_text(double value) {
  return fmt::format("{}", value);
}

}  // namespace

const char* signal_kind_name(SignalKind kind) noexcept {
  switch (kind) {
    case SignalKind::wideband:
      return "wideband";
    case SignalKind::lorry:
      return "lorry";
    case SignalKind::harmonic:
      return "harmonic";
  }
  return "?";
}

bool parse_signal_kind(const std::string& name, SignalKind& out) noexcept {
  for (SignalKind kind : {SignalKind::wideband, SignalKind::lorry, SignalKind::harmonic}) {
    if (name == signal_kind_name(kind)) {
      out = kind;
      return true;
    }
  }
  return false;
}

void validate(const GeneratorSpec& spec) {
  // isfinite first: no comparison ever touches a NaN (that would raise FE_INVALID).
  const auto positive = [](const char* option, double value) {
    if (!std::isfinite(value) || !(value > 0.0)) {
      throw UsageError(std::string(option) + ": must be a finite number > 0, got " +
                       number_text(value));
    }
  };
  positive("--rms", spec.rms_m_per_s2);
  positive("--duration", spec.duration_s);
  positive("--dt", spec.dt_s);
  const double steps = spec.duration_s / spec.dt_s;
  if (!(steps <= kMaxGeneratedSamples)) {
    throw UsageError(
        fmt::format("--duration/--dt: {} s / {} s = {} samples, more than the limit {}",
                    spec.duration_s, spec.dt_s, steps, kMaxGeneratedSamples));
  }
  if (std::llround(steps) < 1) {
    throw UsageError(fmt::format("--duration/--dt: {} s is shorter than one step of {} s",
                                 spec.duration_s, spec.dt_s));
  }
  const double nyquist_hz = 0.5 / spec.dt_s;
  if (spec.kind == SignalKind::harmonic) {
    if (!std::isfinite(spec.frequency_hz) || !(spec.frequency_hz > 0.0) ||
        !(spec.frequency_hz < nyquist_hz)) {
      throw UsageError(
          fmt::format("--frequency: harmonic needs 0 < frequency < 0.5/dt = {} Hz, got {}",
                      nyquist_hz, spec.frequency_hz));
    }
  } else if (!(kWidebandHighHz < nyquist_hz)) {
    throw UsageError(fmt::format("--dt: {} needs 0.5/dt above {} Hz, i.e. dt < {} s; got dt = {} s",
                                 signal_kind_name(spec.kind), kWidebandHighHz,
                                 0.5 / kWidebandHighHz, spec.dt_s));
  }
}

std::uint64_t sample_count(const GeneratorSpec& spec) {
  return static_cast<std::uint64_t>(std::llround(spec.duration_s / spec.dt_s)) + 1;
}

void generate(const GeneratorSpec& spec,
              const std::function<void(std::uint64_t, double, double)>& sink) {
  validate(spec);
  const std::uint64_t count = sample_count(spec);
  CompensatedSum sum_of_squares;
  {
    SignalStream stream(spec);
    for (std::uint64_t n = 0; n < count; ++n) {
      const double value = stream.next();
      sum_of_squares.add(value * value);
    }
  }
  const double raw_rms = std::sqrt(sum_of_squares.value() / static_cast<double>(count));
  if (!(raw_rms > 0.0) || !std::isfinite(raw_rms)) {
    throw UsageError(fmt::format("{}: the signal is identically zero for these settings",
                                 signal_kind_name(spec.kind)));
  }
  const double scale = spec.rms_m_per_s2 / raw_rms;
  SignalStream stream(spec);  // the same stream again: identical raw values
  for (std::uint64_t n = 0; n < count; ++n) {
    sink(n, static_cast<double>(n) * spec.dt_s, scale * stream.next());
  }
}

std::vector<double> generate_signal(const GeneratorSpec& spec) {
  validate(spec);
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(sample_count(spec)));
  generate(spec, [&out](std::uint64_t, double, double a_u) { out.push_back(a_u); });
  return out;
}

std::uint64_t write_generated_csv(const GeneratorSpec& spec, const std::string& path) {
  validate(spec);
  AtomicOutputFile file(path);
  CsvWriter writer(file);
  writer.text("t,a_u\n");
  std::uint64_t rows = 0;
  generate(spec, [&](std::uint64_t, double t_s, double a_u) {
    writer.number(t_s);
    writer.separator();
    writer.number(a_u);
    writer.end_row();
    ++rows;
  });
  writer.flush();
  file.commit();
  return rows;
}

}  // namespace stickslip::host
