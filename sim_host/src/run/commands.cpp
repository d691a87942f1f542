#include "stickslip/host/run/commands.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <ostream>
#include <system_error>
#include <utility>
#include <vector>

#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/stats_json.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::host {
namespace {

// The option that sets each OscillatorParams field, to point the user at what to change.
const char* option_for(const std::string& parameter) {
  static const struct {
    const char* parameter;
    const char* option;
  } table[] = {{"mass_kg", "--mass"},
               {"stiffness_n_per_m", "--stiffness"},
               {"damping_ns_per_m", "--damping"},
               {"kinetic_friction_n", "--ffk"},
               {"static_friction_n", "--ffs"},
               {"stribeck_velocity_m_per_s", "--stribeck-velocity"},
               {"smoothing_constant_s_per_m", "--smoothing-c"},
               {"model", "--model"},
               {"smoothing", "--smoothing"},
               {"input_range_m_per_s2", "--input-range"},
               {"displacement_range_m", "--displacement-range"},
               {"integrator", "--integrator"}};
  for (const auto& entry : table)
    if (parameter == entry.parameter) return entry.option;
  return nullptr;
}

// "--mass: mass_kg: must be >= 1e-06 ..." or, for the step, "IN.csv: dt_s: ..." (dt comes from t).
std::string explain_configuration_error(const std::string& core_message,
                                        const std::string& input_path, double dt_s) {
  const std::string parameter = core_message.substr(0, core_message.find(':'));
  if (parameter == "dt_s") {
    return fmt::format("{}: the time step of the file (dt = {} s) does not suit this model: {}",
                       input_path, dt_s, core_message);
  }
  if (const char* option = option_for(parameter)) return std::string(option) + ": " + core_message;
  return "invalid parameters: " + core_message;
}

template <typename T>
void write_trace(CsvWriter& writer, const SampledSignal& signal, const SimulationTrace<T>& trace) {
  writer.text(kSimulateHeader);
  writer.text("\n");
  const std::size_t count = signal.t_s.size();
  for (std::size_t n = 0; n < count; ++n) {
    writer.number(signal.t_s[n]);  // t and a_u echo the input exactly
    writer.separator();
    writer.number(signal.a_u_m_per_s2[n]);
    writer.separator();
    writer.number(static_cast<double>(trace.x_r_m[n]));
    writer.separator();
    writer.number(static_cast<double>(trace.v_r_m_per_s[n]));
    writer.separator();
    writer.number(static_cast<double>(trace.a_x_m_per_s2[n]));
    writer.separator();
    writer.number(static_cast<double>(trace.friction_n[n]));
    writer.separator();
    writer.flag(trace.stuck[n] != 0);
    writer.end_row();
  }
  writer.flush();
}

template <typename T>
SimulationSummary run_and_write(const SimulationSetup& setup, const SampledSignal& signal,
                                const std::vector<T>& a_u, CsvWriter& writer,
                                const std::string& input_path) {
  SimulationTrace<T> trace;
  SimulationSummary summary;
  try {
    summary = simulate_signal(setup, a_u, trace);
  } catch (const ConfigurationError& error) {
    throw HostError(explain_configuration_error(error.what(), input_path, setup.params.dt_s));
  }
  add_ride_comfort(summary, signal.a_u_m_per_s2, trace.a_x_m_per_s2, setup.params.dt_s);
  write_trace(writer, signal, trace);
  return summary;
}

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

std::string make_fresh_directory() {
  std::error_code error;
  std::filesystem::path base = std::filesystem::temp_directory_path(error);
  if (error) base = ".";
  std::string pattern = (base / "stickslip-demo-XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (::mkdtemp(buffer.data()) == nullptr) {
    throw HostError(pattern + ": cannot create a demo directory: " + std::strerror(errno));
  }
  return std::string(buffer.data());
}

}  // namespace

SimulateResult simulate_file(const SimulateRequest& request) {
  require_finite("--x0", request.setup.x0_m);
  require_finite("--v0", request.setup.v0_m_per_s);
  if (request.setup.reference &&
      (request.scalar == ScalarType::fixed || request.scalar == ScalarType::fixed32)) {
    throw UsageError(std::string("--scalar ") + scalar_name(request.scalar) +
                     ": the reference integrator runs in double only; use --scalar double");
  }
  if (request.setup.reference && request.scalar == ScalarType::float32) {
    throw UsageError(
        "--scalar float: the reference integrator runs in double only (long double inside); "
        "use --scalar double");
  }
  if (!request.stats_path.empty()) {
    std::error_code error;
    if (request.stats_path == request.output_path ||
        std::filesystem::equivalent(request.stats_path, request.output_path, error)) {
      throw UsageError("--stats and --output name the same file: " + request.output_path);
    }
  }
  if ((request.setup.effects & kEndStops) &&
      (request.setup.reference || request.scalar == ScalarType::fixed ||
       request.scalar == ScalarType::fixed32)) {
    throw UsageError(
        "--scene: end stops run in double or float with the core's exact integrator "
        "(not --integrator reference, not --scalar fixed)");
  }
  const SampledSignal signal = read_signal_file(request.input_path);  // CSV or .mat
  if (request.scene_dt_s > 0.0 &&
      std::fabs(signal.dt_s - request.scene_dt_s) > 1e-9 * request.scene_dt_s) {
    throw HostError(fmt::format(
        "{}: dt = {} s, but the scene {} has sample_rate_hz = {} (dt = {} s)", request.input_path,
        signal.dt_s, request.scene_path, 1.0 / request.scene_dt_s, request.scene_dt_s));
  }
  SimulationSetup setup = request.setup;
  setup.params.dt_s = signal.dt_s;

  // Temporaries first: a bad output path fails before the work; any later failure removes them.
  AtomicOutputFile output(request.output_path);
  std::optional<AtomicOutputFile> stats;
  if (!request.stats_path.empty()) stats.emplace(request.stats_path);
  CsvWriter writer(output);

  SimulateResult result;
  if (request.scalar == ScalarType::fixed || request.scalar == ScalarType::fixed32) {
    SimulationTrace<double> trace;
    try {
      result.summary = request.scalar == ScalarType::fixed
                           ? simulate_signal_fixed(setup, signal.a_u_m_per_s2, trace)
                           : simulate_signal_fixed32(setup, signal.a_u_m_per_s2, trace);
      add_ride_comfort(result.summary, signal.a_u_m_per_s2, trace.a_x_m_per_s2, setup.params.dt_s);
    } catch (const ConfigurationError& error) {
      throw HostError(
          explain_configuration_error(error.what(), request.input_path, setup.params.dt_s));
    }
    write_trace(writer, signal, trace);
  } else if (request.scalar == ScalarType::float32) {
    // Converted once, before the loop: the float run sees only floats (and only finite ones).
    for (std::size_t n = 0; n < signal.a_u_m_per_s2.size(); ++n) {
      if (std::fabs(signal.a_u_m_per_s2[n]) > static_cast<double>(FLT_MAX)) {
        throw HostError(
            fmt::format("{}: a_u = {} at t = {} s is beyond the range of a float "
                        "(--scalar float)",
                        request.input_path, signal.a_u_m_per_s2[n], signal.t_s[n]));
      }
    }
    const std::vector<float> a_u(signal.a_u_m_per_s2.begin(), signal.a_u_m_per_s2.end());
    result.summary = run_and_write(setup, signal, a_u, writer, request.input_path);
  } else {
    result.summary = run_and_write(setup, signal, signal.a_u_m_per_s2, writer, request.input_path);
  }
  result.stats_json = format_stats_json(
      result.summary,
      StatsContext{&setup, request.scalar, request.input_path, request.output_path});
  if (setup.reference) {
    // The core's Integrator has no 'reference': name the solver that ran.
    auto json = nlohmann::ordered_json::parse(result.stats_json);
    json["integrator"] = "reference";
    result.stats_json = json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  }
  if (stats) stats->write(result.stats_json + "\n");

  output.commit();
  if (stats) {
    try {
      stats->commit();
    } catch (...) {
      std::remove(request.output_path.c_str());  // all or nothing
      throw;
    }
  }
  return result;
}

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

  std::string directory = request.out_dir;
  if (directory.empty()) {
    directory = make_fresh_directory();
  } else {
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error) throw HostError(directory + ": cannot create the directory: " + error.message());
  }
  const std::filesystem::path dir(directory);
  const std::string recording_path = (dir / "lorry.csv").string();
  write_generated_csv(recording, recording_path);

  // The cheap model as users run it (signum on Simulink's ode1, which chatters once the seat
  // should stick), the same law integrated exactly, and the stick-slip model.
  struct Row {
    FrictionModel model;
    Integrator integrator;
    SimulateResult result;
  };
  const std::pair<FrictionModel, Integrator> runs[] = {
      {FrictionModel::signum, Integrator::euler},
      {FrictionModel::signum, Integrator::exact},
      {FrictionModel::stick_slip, Integrator::exact}};
  std::vector<Row> rows;
  for (const auto& [model, integrator] : runs) {
    const std::string stem = fmt::format("{}-{}", model_name(model), integrator_name(integrator));
    SimulateRequest run;
    run.input_path = recording_path;
    run.output_path = (dir / (stem + ".csv")).string();
    run.stats_path = (dir / (stem + ".json")).string();
    OscillatorParams& p = run.setup.params;  // defaults: the reference system
    p.mass_kg = 88.4;
    p.stiffness_n_per_m = 11500.0;
    p.damping_ns_per_m = 504.0;
    p.kinetic_friction_n = request.friction_n;
    p.static_friction_n = request.friction_n;
    p.model = model;
    p.integrator = integrator;
    rows.push_back({model, integrator, simulate_file(run)});
  }

  out << fmt::format(
      "lorry recording: {} s at dt = {} s, rms 0.35 m/s^2, seed 1; seat: m = 88.4 kg, "
      "k = 11500 N/m, b = 504 N s/m, F_fk = F_fs = {} N\n\n",
      request.duration_s, request.dt_s, request.friction_n);
  out << fmt::format("{:<12}{:<12}{:>12}{:>8}{:>8}{:>8}{:>11}\n", "model", "integrator",
                     "a0u [m/s^2]", "K", "T_ax", "p", "ns/sample");
  for (const Row& row : rows) {
    const SimulationSummary& s = row.result.summary;
    out << fmt::format("{:<12}{:<12}{:>12.4f}{:>8.3f}{:>8.3f}{:>8.3f}{:>11.1f}\n",
                       model_name(row.model), integrator_name(row.integrator), s.rms_u,
                       s.den_hartog_k, s.transmissibility, s.stick_probability, s.ns_per_sample);
  }

  const SimulationSummary& signum = rows[0].result.summary;  // ode1, the cheap model
  const SimulationSummary& stick_slip = rows[2].result.summary;
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

  // The same recording as the ECU sees it: streamed as CAN frames over the default bus (vcan0
  // where the kernel has it, else the in-process loopback bus) to the ECU node running
  // stick-slip; then simulate on the quantised samples, which must give the same file.
  ReplayRequest replay;
  replay.input_path = recording_path;
  replay.bus = request.bus.empty() ? port::default_bus_name() : request.bus;
  replay.output_path = (dir / "stick-slip-replay.csv").string();
  OscillatorParams& rp = replay.setup.params;
  rp.mass_kg = 88.4;
  rp.stiffness_n_per_m = 11500.0;
  rp.damping_ns_per_m = 504.0;
  rp.kinetic_friction_n = rp.static_friction_n = request.friction_n;
  rp.model = FrictionModel::stick_slip;
  rp.integrator = Integrator::exact;
  const ReplayResult replayed = replay_file(replay);
  SimulateRequest quantised;
  quantised.input_path = replay.output_path;  // its t and a_u columns: the quantised samples
  quantised.output_path = (dir / "stick-slip-quantised.csv").string();
  quantised.setup.params = rp;
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
  out << "files: " << directory
      << " (lorry.csv; signum-euler, signum-exact, stick-slip-exact .csv/.json; "
         "stick-slip-replay.csv, stick-slip-quantised.csv)\n";
}

}  // namespace stickslip::host
