// stickslip psd, harmonic-balance and advise: a recording's spectrum, Den Hartog's amplitude
// against simulation, and the cheapest model for a recording (welch.hpp, harmonic_balance.hpp,
// advise.hpp).
#include <fmt/format.h>

#include <ostream>
#include <vector>

#include "command.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/advise.hpp"
#include "stickslip/host/run/harmonic_balance.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/welch.hpp"

namespace stickslip::host {
namespace {

void write_psd_csv(const Spectrum& spectrum, const TargetSpectrum* target,
                   const std::string& path) {
  AtomicOutputFile file(path);
  CsvWriter writer(file);
  writer.text(target ? "f_hz,psd,target\n" : "f_hz,psd\n");
  for (std::size_t k = 0; k < spectrum.psd.size(); ++k) {
    writer.number(spectrum.frequency_hz[k]);
    writer.separator();
    writer.number(spectrum.psd[k]);
    if (target) {
      writer.separator();
      writer.number(target_psd(*target, spectrum.frequency_hz[k]));
    }
    writer.end_row();
  }
  writer.flush();
  file.commit();
}

class PsdCommand : public Command {
 public:
  void add_options(Options& psd) override {
    psd.add_option("--input", input_, "recording (CSV t,a_u, .mat, a logger's text, a CAN log)")
        ->required();
    psd.add_option("--segment", segment_, "samples per segment, a power of two")
        ->capture_default_str();
    psd.add_option("--target", target_,
                   "also a column `target`: the PSD of this seat-test class (EM1..AG3)");
    psd.add_option("--output", output_, "CSV file to write")->required();
    recording_.add_to(psd);
  }

  int run(Options&, std::ostream& out, std::ostream& err) override {
    const RecordingOptions recording = recording_.resolve();
    const TargetSpectrum* target = nullptr;
    if (!target_.empty()) {
      target = find_seat_test_spectrum(target_);
      if (target == nullptr) {
        throw UsageError("--target: unknown class '" + target_ + "' (expected one of " +
                         spectrum_kind_names() + " except white)");
      }
    }
    const LoadedRecording loaded = read_recording(input_, recording);
    std::size_t short_samples = 0;
    std::vector<const std::vector<double>*> parts;
    for (const SampledSignal& part : loaded.segments) parts.push_back(&part.a_u_m_per_s2);
    const Spectrum spectrum =
        welch_psd_over_parts(parts, loaded.segments.front().dt_s, segment_, short_samples);
    write_psd_csv(spectrum, target, output_);
    print_recording_report(err, input_, loaded.report);
    out << fmt::format("wrote {}: {} frequencies, {} segments", output_, spectrum.psd.size(),
                       spectrum.segments);
    if (loaded.segments.size() > 1) {
      out << fmt::format(" over {} parts between gaps", loaded.segments.size());
      if (short_samples > 0)
        out << fmt::format(" ({} samples in parts shorter than --segment not used)", short_samples);
    }
    out << "\n";
    return kExitOk;
  }

 private:
  std::string input_, output_;
  std::size_t segment_ = 4096;
  std::string target_;
  RecordingOptionGroup recording_;
};

class HarmonicBalanceCommand : public Command {
 public:
  void add_options(Options& hb) override {
    hb.add_option("--frequency", request_.frequency_hz, "excitation frequency, Hz")
        ->capture_default_str();
    hb.add_option("--amplitude", request_.amplitude_m_per_s2, "A, m/s^2")->capture_default_str();
    hb.add_option("--damping", request_.damping_ns_per_m, "b values, N s/m (comma-separated)")
        ->delimiter(',')
        ->capture_default_str();
    hb.add_option("--k-range", request_.k_range, "MIN:MAX:COUNT")->capture_default_str();
    add_seat_options(hb, request_.mass_kg, request_.stiffness_n_per_m);
    hb.add_option("--dt", request_.dt_s, "s")->capture_default_str();
    hb.add_option("--periods", request_.periods,
                  "excitation periods simulated (the last quarter measured)")
        ->capture_default_str();
    hb.add_option("--output", output_, "CSV file to write")->required();
  }

  int run(Options&, std::ostream& out, std::ostream&) override {
    const std::size_t rows = write_harmonic_balance_sweep(request_, output_);
    out << fmt::format("wrote {}: {} rows\n", output_, rows);
    return kExitOk;
  }

 private:
  HarmonicBalanceSweepRequest request_;
  std::string output_;
};

class AdviseCommand : public Command {
 public:
  void add_options(Options& advise) override {
    OscillatorParams& p = request_.params;
    advise
        .add_option("--input", request_.input_path,
                    "recording (CSV t,a_u, .mat, a logger's text, a CAN log with --dbc)")
        ->required();
    add_seat_options(advise, p.mass_kg, p.stiffness_n_per_m);
    advise.add_option("--damping", p.damping_ns_per_m, "damper b, N s/m")->capture_default_str();
    add_friction_options(advise, p, true);
    advise.add_option("--tolerance", request_.tolerance, "largest relative T_ax error accepted")
        ->capture_default_str();
    recording_.add_to(advise);
  }

  int run(Options& advise_command, std::ostream& out, std::ostream& err) override {
    AdviseRequest request = request_;
    request.recording = recording_.resolve();
    default_static_friction(advise_command, request.params, nullptr);
    const AdviseReport report = advise(request);
    if (!report.recording_note.empty()) err << "stickslip: " << report.recording_note << "\n";
    out << format_advice(report);
    return kExitOk;
  }

 private:
  AdviseRequest request_;
  RecordingOptionGroup recording_;
};

}  // namespace

std::unique_ptr<Command> make_psd_command() {
  return std::make_unique<PsdCommand>();
}

std::unique_ptr<Command> make_harmonic_balance_command() {
  return std::make_unique<HarmonicBalanceCommand>();
}

std::unique_ptr<Command> make_advise_command() {
  return std::make_unique<AdviseCommand>();
}

}  // namespace stickslip::host
