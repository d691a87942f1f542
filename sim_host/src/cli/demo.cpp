#include "stickslip/host/cli/demo.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <system_error>
#include <utility>
#include <vector>

#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/simulate_file.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::host {
namespace {

void require_finite(const char* option, double value) {
  if (!std::isfinite(value))
    throw UsageError(fmt::format("{}: must be a finite number, got {}", option, value));
}

std::string read_file(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw HostError(path + ": cannot read: " + std::strerror(errno));
  std::string text;
  char buffer[1 << 16];
  for (std::size_t got; (got = std::fread(buffer, 1, sizeof buffer, file)) > 0;)
    text.append(buffer, got);
  std::fclose(file);
  return text;
}

// The cheap model as users run it (signum on Simulink's ode1, which chatters once the seat
// should stick), the same law integrated exactly, and the stick-slip model.
struct DemoRun {
  FrictionModel model;
  Integrator integrator;
  SimulateResult result;
};

// The reference seat with F_fk = F_fs = friction_n.
OscillatorParams reference_seat(double friction_n, FrictionModel model, Integrator integrator) {
  OscillatorParams p;
  p.mass_kg = 88.4;
  p.stiffness_n_per_m = 11500.0;
  p.damping_ns_per_m = 504.0;
  p.kinetic_friction_n = friction_n;
  p.static_friction_n = friction_n;
  p.model = model;
  p.integrator = integrator;
  return p;
}

// Every file the demo writes into --out-dir, in the order it writes them.
const char* const kDemoFiles[] = {"lorry.csv",
                                  "signum-euler.csv",
                                  "signum-euler.json",
                                  "signum-exact.csv",
                                  "signum-exact.json",
                                  "stick-slip-exact.csv",
                                  "stick-slip-exact.json",
                                  "stick-slip-replay.csv",
                                  "stick-slip-quantised.csv"};

// With --no-clobber, before anything is written: a file of an earlier demo (or the user's) is
// kept, and nothing is written beside it.
void refuse_existing_files(const std::filesystem::path& dir) {
  for (const char* name : kDemoFiles) {
    std::error_code error;
    const std::filesystem::path path = dir / name;
    if (std::filesystem::exists(path, error)) {
      throw HostError("--out-dir " + dir.string() + ": " + name +
                      " exists, and --no-clobber keeps it (nothing written)");
    }
  }
}

std::string prepare_directory(const std::string& out_dir) {
  if (out_dir.empty()) throw UsageError("--out-dir: empty directory name");
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) throw HostError(out_dir + ": cannot create the directory: " + error.message());
  return out_dir;
}

std::vector<DemoRun> simulate_three_ways(const std::string& recording_path,
                                         const std::filesystem::path& dir, double friction_n) {
  const std::pair<FrictionModel, Integrator> runs[] = {
      {FrictionModel::signum, Integrator::euler},
      {FrictionModel::signum, Integrator::exact},
      {FrictionModel::stick_slip, Integrator::exact}};
  std::vector<DemoRun> rows;
  for (const auto& [model, integrator] : runs) {
    const std::string stem = fmt::format("{}-{}", model_name(model), integrator_name(integrator));
    SimulateRequest run;
    run.input_path = recording_path;
    run.output_path = (dir / (stem + ".csv")).string();
    run.stats_path = (dir / (stem + ".json")).string();
    run.setup.params = reference_seat(friction_n, model, integrator);
    rows.push_back({model, integrator, simulate_file(run)});
  }
  return rows;
}

void print_table(const DemoRequest& request, const std::vector<DemoRun>& rows, std::ostream& out) {
  out << fmt::format(
      "lorry recording: {} s at dt = {} s, rms 0.35 m/s^2, seed 1; seat: m = 88.4 kg, "
      "k = 11500 N/m, b = 504 N s/m, F_fk = F_fs = {} N\n\n",
      request.duration_s, request.dt_s, request.friction_n);
  out << fmt::format("{:<12}{:<12}{:>12}{:>8}{:>8}{:>8}{:>11}\n", "model", "integrator",
                     "a0u [m/s^2]", "K", "T_ax", "p", "ns/sample");
  for (const DemoRun& row : rows) {
    const SimulationSummary& s = row.result.summary;
    out << fmt::format("{:<12}{:<12}{:>12.4f}{:>8.3f}{:>8.3f}{:>8.3f}{:>11.1f}\n",
                       model_name(row.model), integrator_name(row.integrator), s.rms_u,
                       s.den_hartog_k, s.transmissibility, s.stick_probability, s.ns_per_sample);
  }
}

void print_verdict(const SimulationSummary& signum, const SimulationSummary& stick_slip,
                   std::ostream& out) {
  const double k = stick_slip.den_hartog_k;
  const double difference = signum.transmissibility - stick_slip.transmissibility;
  const double relative =
      stick_slip.transmissibility > 0.0 ? 100.0 * difference / stick_slip.transmissibility : 0.0;
  const std::string t_ax = fmt::format(
      "signum (ode1) gives T_ax = {:.3f}, stick-slip {:.3f} (difference {:+.3f}, {:+.1f} %)",
      signum.transmissibility, stick_slip.transmissibility, difference, relative);
  out << "\n";
  switch (friction_regime(k)) {
    case FrictionRegime::signum_suffices:
      out << fmt::format(
          "K = {:.2f} < {}: signum suffices - the cheap signum model is enough for this "
          "scene; {}.\n",
          k, kSignumSufficesBelowK, t_ax);
      break;
    case FrictionRegime::transition:
      out << fmt::format(
          "K = {:.2f} is in the transition band {}..{}: signum is borderline, use "
          "stick-slip to be safe; {}.\n",
          k, kSignumSufficesBelowK, kStickSlipRequiredAboveK, t_ax);
      break;
    case FrictionRegime::stick_slip_required:
      out << fmt::format(
          "K = {:.2f} > {}: stick-slip required - the seat sticks much of the time "
          "and this scene needs the stick-slip model; {}.\n",
          k, kStickSlipRequiredAboveK, t_ax);
      break;
  }
}

// The same recording as the ECU sees it: streamed as CAN frames over the default bus (vcan0
// where the kernel has it, else the in-process loopback bus) to the ECU node running
// stick-slip; then simulate on the quantised samples, which must give the same file.
void replay_and_compare(const DemoRequest& request, const std::string& recording_path,
                        const std::filesystem::path& dir, std::ostream& out) {
  ReplayRequest replay;
  replay.input_path = recording_path;
  replay.bus = request.bus.empty() ? port::default_bus_name() : request.bus;
  replay.output_path = (dir / "stick-slip-replay.csv").string();
  replay.setup.params =
      reference_seat(request.friction_n, FrictionModel::stick_slip, Integrator::exact);
  const ReplayResult replayed = replay_file(replay);
  SimulateRequest quantised;
  quantised.input_path = replay.output_path;  // its t and a_u columns: the quantised samples
  quantised.output_path = (dir / "stick-slip-quantised.csv").string();
  quantised.setup.params = replay.setup.params;
  quantised.setup.repetitions = 1;
  simulate_file(quantised);
  const bool identical = read_file(replay.output_path) == read_file(quantised.output_path);
  out << fmt::format(
      "\nreplay over {} (stick-slip, exact, a_u quantised to 2^-10 m/s^2): {} frames sent, "
      "{} samples, {} output frames; T_ax = {:.3f}, p = {:.3f}\n",
      replayed.bus, replayed.frames_sent, replayed.summary.samples, replayed.output_frames,
      replayed.summary.transmissibility, replayed.summary.stick_probability);
  out << fault_counters_text(replayed.faults) << "\n";
  out << (identical ? "simulate on the quantised samples gives the same output, bit for bit\n"
                    : "MISMATCH: simulate on the quantised samples differs from the replay\n");
  if (!identical) throw HostError("replay and simulate on the quantised samples differ");
}

}  // namespace

void run_demo(const DemoRequest& request, std::ostream& out) {
  require_finite("--ffk", request.friction_n);
  if (!(request.friction_n >= 0.0)) {
    throw UsageError(fmt::format("--ffk: must be >= 0, got {}", request.friction_n));
  }
  GeneratorSpec recording;
  recording.kind = SignalKind::lorry;
  recording.rms_m_per_s2 = 0.35;
  recording.duration_s = request.duration_s;
  recording.dt_s = request.dt_s;
  recording.seed = 1;
  validate(recording);  // before creating any directory

  if (request.no_clobber) refuse_existing_files(request.out_dir);
  const std::string directory = prepare_directory(request.out_dir);
  const std::filesystem::path dir(directory);
  const std::string recording_path = (dir / "lorry.csv").string();
  write_generated_csv(recording, recording_path);

  const std::vector<DemoRun> rows = simulate_three_ways(recording_path, dir, request.friction_n);
  print_table(request, rows, out);
  print_verdict(rows[0].result.summary, rows[2].result.summary, out);  // ode1 vs stick-slip
  replay_and_compare(request, recording_path, dir, out);
  out << "files: " << directory << " (";
  for (const char* name : kDemoFiles) out << (name == kDemoFiles[0] ? "" : ", ") << name;
  out << ")\n";
}

}  // namespace stickslip::host
