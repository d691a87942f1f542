// stickslip generate: a synthetic recording (signal_generator.hpp, seat_test_spectra.hpp).
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <ostream>

#include "command.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/signal_generator.hpp"

namespace stickslip::host {
namespace {

bool is_mat_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == ".mat";
}

class GenerateCommand : public Command {
 public:
  void add_options(Options& generate) override {
    generate
        .add_option(
            "--kind", kind_,
            "wideband | lorry | harmonic | a seat-test spectrum or band-limited white noise: " +
                spectrum_kind_names())
        ->required();
    generate
        .add_option("--rms", generator_.rms_m_per_s2,
                    "RMS of a_u over the file, m/s^2 (seat-test spectra: default the "
                    "standard's level)")
        ->check(OptionCheck::positive);
    generate.add_option("--band-low", band_low_hz_, "white: lower corner, Hz (0: none)")
        ->capture_default_str();
    generate.add_option("--band-high", band_high_hz_, "white: upper corner, Hz")
        ->capture_default_str();
    generate
        .add_option("--duration", generator_.duration_s, "s; samples n = 0..round(duration/dt)")
        ->required();
    generate.add_option("--dt", generator_.dt_s, "sample interval, s")->required();
    generate.add_option("--seed", generator_.seed, "random seed (wideband, lorry)")
        ->capture_default_str();
    generate.add_option("--frequency", generator_.frequency_hz,
                        "Hz, harmonic only (ignored by the other kinds)");
    generate
        .add_option("--output", output_, "CSV file to write (.mat: a MATLAB file of t and a_u)")
        ->required();
  }

  int run(Options& generate, std::ostream& out, std::ostream&) override {
    for (const char* band : {"--band-low", "--band-high"}) {
      if (kind_ != "white" && given(generate, band)) {
        throw UsageError(std::string(band) + ": only --kind white has corners to set; --kind " +
                         kind_ + " has its own band");
      }
    }
    if (run_spectrum(generate, out)) return kExitOk;
    GeneratorSpec spec = generator_;
    if (!parse_signal_kind(kind_, spec.kind)) {
      throw UsageError("--kind: unknown kind '" + kind_ +
                       "' (expected wideband, lorry, harmonic or one of " + spectrum_kind_names() +
                       ")");
    }
    if (!given(generate, "--rms")) throw UsageError("--rms is required");
    std::uint64_t rows = 0;
    if (is_mat_path(output_)) {
      SampledSignal signal;
      host::generate(spec, [&](std::uint64_t, double t_s, double a_u) {
        signal.t_s.push_back(t_s);
        signal.a_u_m_per_s2.push_back(a_u);
      });
      signal.dt_s = spec.dt_s;
      write_signal_mat(output_, signal);
      rows = signal.t_s.size();
    } else {
      rows = write_generated_csv(spec, output_);
    }
    out << fmt::format("wrote {}: {} {} samples, dt = {} s, rms {} m/s^2{}\n", output_, rows,
                       signal_kind_name(spec.kind), spec.dt_s, spec.rms_m_per_s2,
                       spec.kind == SignalKind::harmonic ? fmt::format(", {} Hz", spec.frequency_hz)
                                                         : fmt::format(", seed {}", spec.seed));
    return kExitOk;
  }

 private:
  // Seat-test spectra and white noise (seat_test_spectra.hpp); false for the other kinds.
  bool run_spectrum(const Options& generate, std::ostream& out) const {
    SpectrumSignalSpec spec;
    if (const TargetSpectrum* table = find_seat_test_spectrum(kind_)) {
      spec.spectrum = *table;
    } else if (kind_ == "white") {
      if (!given(generate, "--rms")) throw UsageError("--rms is required for white");
      if (!std::isfinite(band_low_hz_) || !(band_low_hz_ >= 0.0) || !std::isfinite(band_high_hz_) ||
          !(band_high_hz_ > band_low_hz_)) {
        throw UsageError(fmt::format("--band-low/--band-high: need 0 <= low < high, got {} and {}",
                                     band_low_hz_, band_high_hz_));
      }
      spec.spectrum = white_noise_spectrum(band_low_hz_, band_high_hz_, 1.0);
    } else {
      return false;
    }
    spec.rms_m_per_s2 = given(generate, "--rms") ? generator_.rms_m_per_s2 : 0.0;
    spec.duration_s = generator_.duration_s;
    spec.dt_s = generator_.dt_s;
    spec.seed = generator_.seed;
    validate(spec);
    const double rms = requested_rms(spec);
    std::uint64_t rows = 0;
    if (is_mat_path(output_)) {
      SampledSignal signal;
      signal.a_u_m_per_s2 = generate_spectrum_signal(spec);
      signal.dt_s = spec.dt_s;
      for (std::size_t n = 0; n < signal.a_u_m_per_s2.size(); ++n)
        signal.t_s.push_back(static_cast<double>(n) * spec.dt_s);  // as the CSV writes t
      write_signal_mat(output_, signal);
      rows = signal.t_s.size();
    } else {
      rows = write_spectrum_csv(spec, output_);
    }
    out << fmt::format("wrote {}: {} {} samples, dt = {} s, {} {} m/s^2, seed {}\n", output_, rows,
                       spec.spectrum.name, spec.dt_s,
                       spec.rms_m_per_s2 > 0.0 ? "rms" : "the standard's PSD, expected rms", rms,
                       spec.seed);
    return true;
  }

  std::string kind_;
  GeneratorSpec generator_;
  std::string output_;
  double band_low_hz_ = 0.5;  // white
  double band_high_hz_ = 20.0;
};

}  // namespace

std::unique_ptr<Command> make_generate_command() {
  return std::make_unique<GenerateCommand>();
}

}  // namespace stickslip::host
