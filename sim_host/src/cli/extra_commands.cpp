#include "extra_commands.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <ostream>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/advise.hpp"
#include "stickslip/host/run/harmonic_balance.hpp"
#include "stickslip/host/run/sweep.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/welch.hpp"

namespace stickslip::host {

struct ExtraCommandOptions {
  // sweep
  SweepRequest sweep;
  std::vector<std::string> methods = {"signum:euler", "stick-slip:exact"};
  std::string k_range;  // "min:max:count"
  std::string vary = "friction";
  std::string shard;
  std::string sweep_output;
  bool no_batch = false;
  bool quiet = false;
  // merge
  std::vector<std::string> merge_inputs;
  std::string merge_output;
  // psd
  std::string psd_input, psd_output;
  std::size_t psd_segment = 4096;
  std::string psd_target;
  // harmonic-balance
  HarmonicBalanceSweepRequest hb;
  std::string hb_output;
  // advise
  AdviseRequest advise;
  std::string advise_ffs_given;
};

namespace {

std::vector<double> k_values_from_range(const std::string& text) {
  double low = 0.0, high = 0.0;
  int count = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf:%d%c", &low, &high, &count, &tail) != 3 || count < 1 ||
      !(high >= low) || (count == 1 && high != low)) {
    throw UsageError("--k-range: expected MIN:MAX:COUNT with MIN <= MAX, COUNT >= 1, got '" + text +
                     "'");
  }
  std::vector<double> values;
  for (int i = 0; i < count; ++i)
    values.push_back(count == 1 ? low : low + (high - low) * i / (count - 1));
  return values;
}

void parse_shard(const std::string& text, SweepRequest& request) {
  unsigned index = 0, count = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%u/%u%c", &index, &count, &tail) != 2 || count < 1 || index < 1 ||
      index > count) {
    throw UsageError("--shard: expected I/N with 1 <= I <= N, got '" + text + "'");
  }
  request.shard_index = index;
  request.shard_count = count;
}

bool stderr_is_terminal(const std::ostream& err) {
  return &err == &std::cerr && ::isatty(2) == 1;
}

}  // namespace

ExtraCommands::ExtraCommands() : options_(std::make_unique<ExtraCommandOptions>()) {}
ExtraCommands::~ExtraCommands() = default;

bool ExtraCommands::is_name(const std::string& subcommand) {
  return subcommand == "sweep" || subcommand == "merge" || subcommand == "psd" ||
         subcommand == "harmonic-balance" || subcommand == "advise";
}

const char* ExtraCommands::names() {
  return "sweep, merge, psd, harmonic-balance or advise";
}

void ExtraCommands::add_to(CLI::App& app) {
  ExtraCommandOptions& o = *options_;
  CLI::App* sweep = app.add_subcommand(
      "sweep",
      "T_ax and p against Den Hartog's K for recordings x models/integrators x damping values, "
      "on all cores; CSV out (one row per point, in a fixed order)");
  sweep->add_option("--input", o.sweep.inputs, "recording (CSV t,a_u or .mat); repeat for more")
      ->required();
  sweep
      ->add_option("--method", o.methods,
                   "MODEL[:INTEGRATOR], repeat or comma-separate (default signum:euler and "
                   "stick-slip:exact)")
      ->delimiter(',');
  sweep->add_option("--damping", o.sweep.damping_ns_per_m, "b values, N s/m (comma-separated)")
      ->delimiter(',')
      ->required();
  sweep->add_option("--k", o.sweep.k_values, "K values (comma-separated)")->delimiter(',');
  sweep->add_option("--k-range", o.k_range, "MIN:MAX:COUNT, evenly spaced K values");
  sweep
      ->add_option("--vary", o.vary,
                   "friction (F_fk from K at the recording's a0u) | excitation (the recording "
                   "scaled to the a0u of K at --ffk)")
      ->capture_default_str();
  sweep->add_option("--ffk", o.sweep.friction_n, "F_fk, N (--vary excitation)")
      ->capture_default_str();
  sweep->add_option("--ffs-ratio", o.sweep.static_friction_ratio, "F_fs / F_fk")
      ->capture_default_str();
  sweep->add_option("--mass", o.sweep.mass_kg, "m, kg")->capture_default_str();
  sweep->add_option("--stiffness", o.sweep.stiffness_n_per_m, "k, N/m")->capture_default_str();
  sweep->add_option("--threads", o.sweep.threads, "worker threads (default: all cores)");
  sweep->add_option(
      "--shard", o.shard,
      "I/N: run only the points with index % N == I - 1 (join with `stickslip merge`)");
  sweep->add_flag("--no-batch", o.no_batch, "step every point alone (same results, slower)");
  sweep->add_flag("--quiet", o.quiet, "no progress on stderr");
  sweep->add_option("--output", o.sweep_output, "CSV file to write")->required();

  CLI::App* merge = app.add_subcommand(
      "merge", "Join the shard files of a sweep into the CSV one unsharded run writes");
  merge->add_option("shards", o.merge_inputs, "shard CSV files (any order)")->required();
  merge->add_option("--output", o.merge_output, "CSV file to write")->required();

  CLI::App* psd = app.add_subcommand(
      "psd", "Welch PSD (Hann, 50 % overlap) of a recording's a_u: f_hz,psd in (m/s^2)^2/Hz");
  psd->add_option("--input", o.psd_input, "recording (CSV t,a_u or .mat)")->required();
  psd->add_option("--segment", o.psd_segment, "samples per segment, a power of two")
      ->capture_default_str();
  psd->add_option("--target", o.psd_target,
                  "also a column `target`: the PSD of this seat-test class (EM1..AG3)");
  psd->add_option("--output", o.psd_output, "CSV file to write")->required();

  CLI::App* hb = app.add_subcommand(
      "harmonic-balance",
      "Den Hartog's harmonic-balance amplitude of x_r under a_u = A sin(2 pi f t) against the "
      "simulated steady state, over K (CSV)");
  hb->add_option("--frequency", o.hb.frequency_hz, "excitation frequency, Hz")
      ->capture_default_str();
  hb->add_option("--amplitude", o.hb.amplitude_m_per_s2, "A, m/s^2")->capture_default_str();
  hb->add_option("--damping", o.hb.damping_ns_per_m, "b values, N s/m (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  hb->add_option("--k-range", o.hb.k_range, "MIN:MAX:COUNT")->capture_default_str();
  hb->add_option("--mass", o.hb.mass_kg, "m, kg")->capture_default_str();
  hb->add_option("--stiffness", o.hb.stiffness_n_per_m, "k, N/m")->capture_default_str();
  hb->add_option("--dt", o.hb.dt_s, "s")->capture_default_str();
  hb->add_option("--periods", o.hb.periods,
                 "excitation periods simulated (the last quarter measured)")
      ->capture_default_str();
  hb->add_option("--output", o.hb_output, "CSV file to write")->required();

  CLI::App* advise = app.add_subcommand(
      "advise",
      "For a recording and seat: a0u, K, p and T_ax of the cheap model against stick-slip, and "
      "the cheapest model/integrator whose T_ax error stays within the tolerance at its dt");
  AdviseRequest& a = o.advise;
  advise->add_option("--input", a.input_path, "recording (CSV t,a_u or .mat)")->required();
  advise->add_option("--mass", a.params.mass_kg, "m, kg")->capture_default_str();
  advise->add_option("--stiffness", a.params.stiffness_n_per_m, "k, N/m")->capture_default_str();
  advise->add_option("--damping", a.params.damping_ns_per_m, "b, N s/m")->capture_default_str();
  advise->add_option("--ffk", a.params.kinetic_friction_n, "F_fk, N")->required();
  advise->add_option("--ffs", o.advise_ffs_given, "F_fs, N (default: F_fk)");
  advise->add_option("--tolerance", a.tolerance, "largest relative T_ax error accepted")
      ->capture_default_str();
}

bool ExtraCommands::run(CLI::App& app, std::ostream& out, std::ostream& err, int& status) {
  ExtraCommandOptions& o = *options_;
  status = 0;
  if (app.got_subcommand("sweep")) {
    SweepRequest request = o.sweep;
    for (const std::string& method : o.methods)
      request.methods.push_back(parse_sweep_method(method));
    if (!o.k_range.empty()) {
      const std::vector<double> range = k_values_from_range(o.k_range);
      request.k_values.insert(request.k_values.end(), range.begin(), range.end());
    }
    if (o.vary == "friction") {
      request.vary = SweepVariable::friction;
    } else if (o.vary == "excitation") {
      request.vary = SweepVariable::excitation;
    } else {
      throw UsageError("--vary: expected friction or excitation, got '" + o.vary + "'");
    }
    if (!o.shard.empty()) {
      parse_shard(o.shard, request);
      request.shard_file = true;
    }
    request.batch = !o.no_batch;
    const SweepProgress progress =
        o.quiet ? SweepProgress() : make_progress_reporter(err, stderr_is_terminal(err));
    const SweepSummary s = run_sweep(request, o.sweep_output, progress);
    out << fmt::format(
        "wrote {}: {} of {} points, {} steps in {:.3f} s on {} threads ({:.1f} Msteps/s)\n",
        o.sweep_output, s.points_run, s.points_total, s.samples, s.seconds, s.threads,
        s.seconds > 0.0 ? static_cast<double>(s.samples) / s.seconds * 1e-6 : 0.0);
    return true;
  }
  if (app.got_subcommand("merge")) {
    merge_sweep_shards(o.merge_inputs, o.merge_output);
    out << fmt::format("wrote {} from {} shards\n", o.merge_output, o.merge_inputs.size());
    return true;
  }
  if (app.got_subcommand("psd")) {
    const TargetSpectrum* target = nullptr;
    if (!o.psd_target.empty()) {
      target = find_seat_test_spectrum(o.psd_target);
      if (target == nullptr) {
        throw UsageError("--target: unknown class '" + o.psd_target + "' (expected one of " +
                         spectrum_kind_names() + " except white)");
      }
    }
    const SampledSignal signal = read_signal_file(o.psd_input);
    const Spectrum spectrum = welch_psd(signal.a_u_m_per_s2, signal.dt_s, o.psd_segment);
    AtomicOutputFile file(o.psd_output);
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
    out << fmt::format("wrote {}: {} frequencies, {} segments\n", o.psd_output, spectrum.psd.size(),
                       spectrum.segments);
    return true;
  }
  if (app.got_subcommand("harmonic-balance")) {
    const std::size_t rows = write_harmonic_balance_sweep(o.hb, o.hb_output);
    out << fmt::format("wrote {}: {} rows\n", o.hb_output, rows);
    return true;
  }
  if (app.got_subcommand("advise")) {
    AdviseRequest request = o.advise;
    if (!o.advise_ffs_given.empty()) {
      try {
        request.params.static_friction_n = std::stod(o.advise_ffs_given);
      } catch (const std::exception&) {
        throw UsageError("--ffs: not a number: '" + o.advise_ffs_given + "'");
      }
    } else {
      request.params.static_friction_n = request.params.kinetic_friction_n;
    }
    const AdviseReport report = advise(request);
    out << format_advice(report);
    return true;
  }
  return false;
}

}  // namespace stickslip::host
