#include "stickslip/host/cli/cli.hpp"

#include <cmath>
#include <csignal>
#include <exception>
#include <new>
#include <ostream>

#include <signal.h>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "extra_commands.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "stickslip/host/run/commands.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/signal_generator.hpp"

namespace stickslip::host {
namespace {

// The model options simulate has (without --integrator reference), for replay and ecu.
struct ModelOptions {
  std::string scene;
  std::string model;
  std::string integrator;
  std::string smoothing = "tanh";
  std::string scalar = "double";
};

// Everything the subcommands can be given; filled by CLI11, checked by the commands.
struct Options {
  // generate
  std::string kind;
  GeneratorSpec generator;
  std::string generate_output;
  double band_low_hz = 0.5;  // white
  double band_high_hz = 20.0;
  // simulate
  SimulateRequest simulate;
  std::string model;
  std::string integrator;
  std::string smoothing = "tanh";
  std::string scalar = "double";
  std::string scene_path;
  // demo
  DemoRequest demo;
  // replay, ecu, record
  ReplayRequest replay;
  EcuRequest ecu;
  RecordRequest record;
  PlayRequest play;
  std::string rate = "max";
  std::string ecu_output;
  ModelOptions replay_model, ecu_model;
};

volatile std::sig_atomic_t stop_requested = 0;

extern "C" void request_stop(int) {
  stop_requested = 1;
}

// SIGINT and SIGTERM set stop_requested while this lives (no SA_RESTART: a blocking receive or
// sleep returns at once); the previous handlers come back with its end.
class StopOnSignals {
 public:
  StopOnSignals() {
    stop_requested = 0;
    struct sigaction action = {};
    action.sa_handler = request_stop;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopOnSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};

// --scene: the file's seat, model, integrator and effects into `setup`, then every flag the
// command was given over them (the flags were parsed into `flags`). Returns the scene.
Scene apply_scene_file(CLI::App& command, const std::string& path, const OscillatorParams& flags,
                       SimulationSetup& setup) {
  const Scene scene = read_scene_file(path);
  OscillatorParams merged = scene.params;
  const auto given = [&](const char* name) {
    const CLI::Option* option = command.get_option_no_throw(name);
    return option != nullptr && option->count() > 0;
  };
  if (given("--mass")) merged.mass_kg = flags.mass_kg;
  if (given("--stiffness")) merged.stiffness_n_per_m = flags.stiffness_n_per_m;
  if (given("--damping")) merged.damping_ns_per_m = flags.damping_ns_per_m;
  if (given("--ffk")) merged.kinetic_friction_n = flags.kinetic_friction_n;
  if (given("--ffs")) merged.static_friction_n = flags.static_friction_n;
  if (given("--ffk") && !given("--ffs") && !(scene.effects & kStaticFriction)) {
    merged.static_friction_n = merged.kinetic_friction_n;
  }
  if (given("--stribeck-velocity"))
    merged.stribeck_velocity_m_per_s = flags.stribeck_velocity_m_per_s;
  if (given("--smoothing-c")) merged.smoothing_constant_s_per_m = flags.smoothing_constant_s_per_m;
  if (given("--input-range")) merged.input_range_m_per_s2 = flags.input_range_m_per_s2;
  if (given("--displacement-range")) merged.displacement_range_m = flags.displacement_range_m;
  merged.dt_s = flags.dt_s;
  setup.params = merged;
  setup.effects = scene.effects;
  setup.stops = scene.stops;
  return scene;
}

// The bus commands run the frame layout of docs/can/stickslip.dbc: a scene that names other
// identifiers is refused rather than silently ignored.
void check_scene_can_ids(const Scene& scene, const std::string& path) {
  if (scene.can.input_id && *scene.can.input_id != can::kSeatInput.id) {
    throw UsageError(
        fmt::format("{}: [can] input_id = 0x{:X}, but this build's frame layout "
                    "(docs/can/stickslip.dbc) receives SeatInput on 0x{:X}",
                    path, *scene.can.input_id, can::kSeatInput.id));
  }
  if (scene.can.output_id && *scene.can.output_id != can::kSeatMotion.id) {
    throw UsageError(
        fmt::format("{}: [can] output_id = 0x{:X}, but this build's frame layout "
                    "(docs/can/stickslip.dbc) publishes from 0x{:X}",
                    path, *scene.can.output_id, can::kSeatMotion.id));
  }
  if (scene.effects & kEndStops) {
    throw UsageError(path +
                     ": the ECU node runs friction scenes without end stops (use simulate "
                     "for a scene with end stops)");
  }
}

void add_model_options(CLI::App* command, SimulationSetup& setup, ModelOptions& m) {
  OscillatorParams& p = setup.params;
  command->add_option("--scene", m.scene,
                      "scene file (TOML, docs/scenes/): seat, model, integrator, sample rate, CAN "
                      "ids; the flags override it");
  command->add_option(
      "--model", m.model,
      "linear | signum | smooth | stick-slip | stribeck (required without --scene)");
  command->add_option("--mass", p.mass_kg, "seat mass m, kg")->capture_default_str();
  command->add_option("--stiffness", p.stiffness_n_per_m, "spring k, N/m")->capture_default_str();
  command->add_option("--damping", p.damping_ns_per_m, "damper b, N s/m")->capture_default_str();
  command->add_option("--ffk", p.kinetic_friction_n, "kinetic friction F_fk, N")
      ->capture_default_str();
  command->add_option("--ffs", p.static_friction_n, "static friction F_fs, N (default: F_fk)");
  command->add_option("--stribeck-velocity", p.stribeck_velocity_m_per_s, "v_S, m/s (stribeck)")
      ->capture_default_str();
  command->add_option("--smoothing", m.smoothing, "atan | tanh | erf | rational (smooth)")
      ->capture_default_str();
  command->add_option("--smoothing-c", p.smoothing_constant_s_per_m, "c in s(c v_r), s/m (smooth)")
      ->capture_default_str();
  command->add_option("--integrator", m.integrator,
                      "euler | symplectic | rk4 | exact (default: exact for linear, signum, "
                      "stick-slip; rk4 for smooth, stribeck)");
  command->add_option("--scalar", m.scalar, "double | float | fixed (Q23.40, as simulate)")
      ->capture_default_str();
  command
      ->add_option("--input-range", p.input_range_m_per_s2,
                   "fixed point: largest |a_u| its scaling must hold, m/s^2")
      ->capture_default_str();
  command
      ->add_option("--displacement-range", p.displacement_range_m,
                   "fixed point: largest |x_r| its scaling must hold, m")
      ->capture_default_str();
  command->add_option("--x0", setup.x0_m, "initial x_r, m")->capture_default_str();
  command->add_option("--v0", setup.v0_m_per_s, "initial v_r, m/s")->capture_default_str();
}

void resolve_model_options(CLI::App& command, const ModelOptions& m, SimulationSetup& setup,
                           ScalarType& scalar, double* scene_dt_s = nullptr) {
  OscillatorParams& p = setup.params;
  const auto given = [&](const char* name) { return command.get_option(name)->count() > 0; };
  const bool scene = !m.scene.empty();
  if (scene) {
    const Scene file = apply_scene_file(command, m.scene, setup.params, setup);
    check_scene_can_ids(file, m.scene);
    if (scene_dt_s && file.sample_rate_hz) *scene_dt_s = 1.0 / *file.sample_rate_hz;
  }
  if (!scene && !given("--model")) throw UsageError("--model is required (or give a --scene)");
  if (scene && !given("--model")) {
    // the scene's model stands
  } else if (!parse_model(m.model.c_str(), p.model)) {
    throw UsageError("--model: unknown model '" + m.model +
                     "' (expected linear, signum, smooth, stick-slip or stribeck)");
  }
  if ((!scene || given("--smoothing")) && !parse_smoothing(m.smoothing.c_str(), p.smoothing)) {
    throw UsageError("--smoothing: unknown form '" + m.smoothing +
                     "' (expected atan, tanh, erf or rational)");
  }
  if (m.integrator.empty()) {
    if (!scene || given("--model")) p.integrator = default_integrator(p.model);
  } else if (!parse_integrator(m.integrator.c_str(), p.integrator)) {
    throw UsageError("--integrator: unknown integrator '" + m.integrator +
                     "' (expected euler, symplectic, rk4 or exact)");
  }
  if (!parse_scalar(m.scalar, scalar)) {
    throw UsageError("--scalar: unknown scalar '" + m.scalar +
                     "' (expected double, float or fixed)");
  }
  if (!scene && !given("--ffs")) p.static_friction_n = p.kinetic_friction_n;
}

void add_checker_options(CLI::App* command, can::CheckerConfig& checker) {
  command
      ->add_option("--max-gap", checker.max_gap,
                   "lost samples held per gap; a longer gap is a counted resync")
      ->capture_default_str();
}

void add_generate(CLI::App& app, Options& o) {
  CLI::App* generate = app.add_subcommand(
      "generate",
      "Write a synthetic cab-floor acceleration a_u(t) as CSV (t,a_u): the same file for "
      "the same options on every machine");
  generate
      ->add_option(
          "--kind", o.kind,
          "wideband | lorry | harmonic | white | a seat-test spectrum: " + spectrum_kind_names())
      ->required();
  generate->add_option("--rms", o.generator.rms_m_per_s2,
                       "RMS of a_u over the file, m/s^2 (seat-test spectra: default the "
                       "standard's level)");
  generate->add_option("--band-low", o.band_low_hz, "white: lower corner, Hz (0: none)")
      ->capture_default_str();
  generate->add_option("--band-high", o.band_high_hz, "white: upper corner, Hz")
      ->capture_default_str();
  generate->add_option("--duration", o.generator.duration_s, "s; samples n = 0..round(duration/dt)")
      ->required();
  generate->add_option("--dt", o.generator.dt_s, "sample interval, s")->required();
  generate->add_option("--seed", o.generator.seed, "random seed (wideband, lorry)")
      ->capture_default_str();
  generate->add_option("--frequency", o.generator.frequency_hz,
                       "Hz, harmonic only (ignored by the other kinds)");
  generate->add_option("--output", o.generate_output, "CSV file to write")->required();
}

void add_simulate(CLI::App& app, Options& o) {
  CLI::App* simulate = app.add_subcommand(
      "simulate",
      "Run the seat model over a recording; write t,a_u,x_r,v_r,a_x,f_f,stuck and print "
      "the statistics as a JSON line");
  OscillatorParams& p = o.simulate.setup.params;
  simulate
      ->add_option("--input", o.simulate.input_path,
                   "CSV with columns t (uniform, s) and a_u (m/s^2)")
      ->required();
  simulate->add_option("--output", o.simulate.output_path, "CSV file to write")->required();
  simulate->add_option("--stats", o.simulate.stats_path, "also write the statistics JSON here");
  simulate->add_option("--scene", o.scene_path,
                       "scene file (TOML, docs/scenes/): effects, seat, model, integrator, sample "
                       "rate; the flags below override it");
  simulate->add_option(
      "--model", o.model,
      "linear | signum | smooth | stick-slip | stribeck (required without --scene)");
  simulate->add_option("--mass", p.mass_kg, "seat mass m, kg")->capture_default_str();
  simulate->add_option("--stiffness", p.stiffness_n_per_m, "spring k, N/m")->capture_default_str();
  simulate->add_option("--damping", p.damping_ns_per_m, "damper b, N s/m")->capture_default_str();
  simulate->add_option("--ffk", p.kinetic_friction_n, "kinetic friction F_fk, N")
      ->capture_default_str();
  simulate->add_option("--ffs", p.static_friction_n, "static friction F_fs, N (default: F_fk)");
  simulate->add_option("--stribeck-velocity", p.stribeck_velocity_m_per_s, "v_S, m/s (stribeck)")
      ->capture_default_str();
  simulate->add_option("--smoothing", o.smoothing, "atan | tanh | erf | rational (smooth)")
      ->capture_default_str();
  simulate->add_option("--smoothing-c", p.smoothing_constant_s_per_m, "c in s(c v_r), s/m (smooth)")
      ->capture_default_str();
  simulate->add_option("--integrator", o.integrator,
                       "euler | symplectic | rk4 | exact | reference (default: exact for "
                       "linear, signum, stick-slip; rk4 for smooth, stribeck; reference: the "
                       "event-driven reference solver, double only)");
  simulate
      ->add_option("--scalar", o.scalar,
                   "double | float | fixed | fixed32 (fixed: Q23.40; fixed32: Q7.24 in scene "
                   "units, as on the Cortex-M0+; both: linear, signum, smooth rational, "
                   "stick-slip; euler, symplectic, exact)")
      ->capture_default_str();
  simulate
      ->add_option("--input-range", p.input_range_m_per_s2,
                   "fixed point: largest |a_u| its scaling must hold, m/s^2")
      ->capture_default_str();
  simulate
      ->add_option("--displacement-range", p.displacement_range_m,
                   "fixed point: largest |x_r| its scaling must hold, m")
      ->capture_default_str();
  simulate->add_option("--x0", o.simulate.setup.x0_m, "initial x_r, m")->capture_default_str();
  simulate->add_option("--v0", o.simulate.setup.v0_m_per_s, "initial v_r, m/s")
      ->capture_default_str();
  simulate
      ->add_option("--repetitions", o.simulate.setup.repetitions,
                   "timed runs for ns_per_sample (default 5; 3 above 2e6 steps)")
      ->check(CLI::PositiveNumber);
}

void add_demo(CLI::App& app, Options& o) {
  CLI::App* demo = app.add_subcommand(
      "demo",
      "Lorry recording -> signum and stick-slip on the reference seat -> which model the "
      "scene needs");
  demo->add_option("--duration", o.demo.duration_s, "s")->capture_default_str();
  demo->add_option("--dt", o.demo.dt_s, "s")->capture_default_str();
  demo->add_option("--ffk", o.demo.friction_n, "F_fk = F_fs, N")->capture_default_str();
  demo->add_option("--bus", o.demo.bus,
                   "bus for the replay (default: vcan0 where the kernel has it, else loopback)");
  demo->add_option(
      "--out-dir", o.demo.out_dir,
      "where the files go (default: a fresh directory under the system temp directory)");
}

void add_replay(CLI::App& app, Options& o) {
  CLI::App* replay = app.add_subcommand(
      "replay",
      "Stream a recording (CSV, or a candump .log) as CAN frames over a bus to the ECU node; "
      "write its samples as simulate does and print the statistics and the fault counters");
  replay->add_option("--input", o.replay.input_path, "CSV (t,a_u) or candump log (*.log)")
      ->required();
  replay->add_option("--bus", o.replay.bus, "loopback | a SocketCAN interface such as vcan0")
      ->capture_default_str();
  replay->add_option("--rate", o.rate, "max | realtime")->capture_default_str();
  replay->add_option("--output", o.replay.output_path, "CSV file to write")->required();
  replay->add_option("--output-log", o.replay.output_log_path,
                     "also write every frame on the bus as a candump log");
  replay->add_option("--dt", o.replay.log_dt_s, "sample interval of a candump-log input, s")
      ->capture_default_str();
  add_checker_options(replay, o.replay.checker);
  add_model_options(replay, o.replay.setup, o.replay_model);
}

void add_ecu(CLI::App& app, Options& o) {
  CLI::App* ecu = app.add_subcommand(
      "ecu", "The ECU node alone on a bus until SIGINT/SIGTERM or --frames; prints its counters");
  ecu->add_option("--bus", o.ecu.bus, "loopback | a SocketCAN interface such as vcan0")->required();
  ecu->add_option(
         "--frames", o.ecu.max_frames,
         "stop after this many frames for the node (all but other nodes' outputs; 0: never)")
      ->capture_default_str();
  ecu->add_option("--dt", o.ecu.setup.params.dt_s, "sample interval of the stream, s")
      ->capture_default_str();
  ecu->add_option("--output", o.ecu_output, "write the node's samples as simulate does");
  ecu->add_option("--receive-buffer", o.ecu.receive_buffer_bytes,
                  "SocketCAN receive buffer (SO_RCVBUF), bytes; 0: the kernel's default")
      ->capture_default_str();
  ecu->add_option("--sample-index", o.ecu.sample_index_path,
                  "write n,sample,held per row: the sender's sample number of each row, 1 if held");
  add_checker_options(ecu, o.ecu.checker);
  add_model_options(ecu, o.ecu.setup, o.ecu_model);
}

void add_play(CLI::App& app, Options& o) {
  CLI::App* play = app.add_subcommand(
      "play",
      "Send a recording's SeatInput frames on a bus at a multiple of real time, without a "
      "node; frames the bus refuses (e.g. while it is down) are counted, not retried");
  play->add_option("--input", o.play.input_path, "CSV (t,a_u) or candump log (*.log)")->required();
  play->add_option("--bus", o.play.bus, "loopback | a SocketCAN interface such as vcan0")
      ->required();
  play->add_option("--speed", o.play.speed, "times real time")->capture_default_str();
  play->add_option("--dt", o.play.log_dt_s, "sample interval of a candump-log input, s")
      ->capture_default_str();
}

void add_record(CLI::App& app, Options& o) {
  CLI::App* record = app.add_subcommand(
      "record",
      "Write a CSV recording as a candump log of SeatInput frames (canplayer replays it)");
  record->add_option("--input", o.record.input_path, "CSV with columns t and a_u")->required();
  record->add_option("--output", o.record.output_path, "candump log to write")->required();
  record->add_option("--interface", o.record.interface, "interface name in the log")
      ->capture_default_str();
}

int run_replay(CLI::App& replay, Options& o, std::ostream& out) {
  ReplayRequest request = o.replay;
  double scene_dt_s = 0.0;
  resolve_model_options(replay, o.replay_model, request.setup, request.scalar, &scene_dt_s);
  if (scene_dt_s > 0.0 && replay.get_option("--dt")->count() == 0) request.log_dt_s = scene_dt_s;
  if (o.rate == "realtime") {
    request.realtime = true;
  } else if (o.rate != "max") {
    throw UsageError("--rate: unknown rate '" + o.rate + "' (expected max or realtime)");
  }
  const ReplayResult result = replay_file(request);
  out << fmt::format(
      "replayed {} over {}: {} frames sent, {} samples, {} output frames ({} seen "
      "back), {} input samples saturated\n",
      request.input_path, result.bus, result.frames_sent, result.summary.samples,
      result.output_frames, result.output_frames_received, result.input_saturated);
  out << fault_counters_text(result.faults) << "\n";
  out << result.stats_json << "\n";  // the last line of stdout, for tools
  return kExitOk;
}

int run_ecu_command(CLI::App& ecu, Options& o, std::ostream& out) {
  EcuRequest request = o.ecu;
  request.output_path = o.ecu_output;
  const double dt_flag_s = request.setup.params.dt_s;
  double scene_dt_s = 0.0;
  resolve_model_options(ecu, o.ecu_model, request.setup, request.scalar, &scene_dt_s);
  request.setup.params.dt_s =
      scene_dt_s > 0.0 && ecu.get_option("--dt")->count() == 0 ? scene_dt_s : dt_flag_s;
  const StopOnSignals signals;
  request.stop = &stop_requested;
  const EcuResult result = run_ecu(request);
  out << fault_counters_text(result.faults) << "\n";
  out << result.json << "\n";
  return kExitOk;
}

int run_play(Options& o, std::ostream& out) {
  PlayRequest request = o.play;
  const StopOnSignals signals;
  request.stop = &stop_requested;
  const PlayResult result = play_file(request);
  out << fmt::format(
      "played {} on {} at {}x: {} of {} frames sent, {} not sent ({} interface "
      "down, {} buffer full, {} other)\n",
      request.input_path, request.bus, request.speed, result.sent, result.frames, result.not_sent,
      result.interface_down, result.buffer_full, result.other_failures);
  out << result.json << "\n";  // the last line of stdout, for tools
  return kExitOk;
}

int run_record(const Options& o, std::ostream& out) {
  std::uint64_t saturated = 0;
  const std::uint64_t frames = record_log(o.record, saturated);
  out << fmt::format("wrote {}: {} SeatInput frames on {}, {} samples saturated\n",
                     o.record.output_path, frames, o.record.interface, saturated);
  return kExitOk;
}

// Seat-test spectra and white noise (seat_test_spectra.hpp); false for the other kinds.
bool run_spectrum_generate(CLI::App& generate, const Options& o, std::ostream& out) {
  SpectrumSignalSpec spec;
  if (const TargetSpectrum* table = find_seat_test_spectrum(o.kind)) {
    spec.spectrum = *table;
  } else if (o.kind == "white") {
    if (generate.get_option("--rms")->count() == 0) throw UsageError("--rms is required for white");
    if (!std::isfinite(o.band_low_hz) || !(o.band_low_hz >= 0.0) ||
        !std::isfinite(o.band_high_hz) || !(o.band_high_hz > o.band_low_hz)) {
      throw UsageError(fmt::format("--band-low/--band-high: need 0 <= low < high, got {} and {}",
                                   o.band_low_hz, o.band_high_hz));
    }
    spec.spectrum = white_noise_spectrum(o.band_low_hz, o.band_high_hz, 1.0);
  } else {
    return false;
  }
  spec.rms_m_per_s2 = generate.get_option("--rms")->count() == 0 ? 0.0 : o.generator.rms_m_per_s2;
  if (generate.get_option("--rms")->count() != 0 && !(spec.rms_m_per_s2 > 0.0)) {
    throw UsageError(fmt::format("--rms: must be a finite number > 0, got {}", spec.rms_m_per_s2));
  }
  spec.duration_s = o.generator.duration_s;
  spec.dt_s = o.generator.dt_s;
  spec.seed = o.generator.seed;
  validate(spec);
  const double rms = requested_rms(spec);
  const std::uint64_t rows = write_spectrum_csv(spec, o.generate_output);
  out << fmt::format("wrote {}: {} {} samples, dt = {} s, {} {} m/s^2, seed {}\n",
                     o.generate_output, rows, spec.spectrum.name, spec.dt_s,
                     spec.rms_m_per_s2 > 0.0 ? "rms" : "the standard's PSD, expected rms", rms,
                     spec.seed);
  return true;
}

int run_generate(CLI::App& generate, const Options& o, std::ostream& out) {
  if (run_spectrum_generate(generate, o, out)) return kExitOk;
  if (generate.get_option("--rms")->count() == 0) throw UsageError("--rms is required");
  GeneratorSpec spec = o.generator;
  if (!parse_signal_kind(o.kind, spec.kind)) {
    throw UsageError("--kind: unknown kind '" + o.kind +
                     "' (expected wideband, lorry, harmonic or one of " + spectrum_kind_names() +
                     ")");
  }
  const std::uint64_t rows = write_generated_csv(spec, o.generate_output);
  out << fmt::format("wrote {}: {} {} samples, dt = {} s, rms {} m/s^2{}\n", o.generate_output,
                     rows, signal_kind_name(spec.kind), spec.dt_s, spec.rms_m_per_s2,
                     spec.kind == SignalKind::harmonic ? fmt::format(", {} Hz", spec.frequency_hz)
                                                       : fmt::format(", seed {}", spec.seed));
  return kExitOk;
}

// simulate --scene: the scene into the request (see apply_scene_file), its sample rate checked
// against the recording's by simulate_file().
void apply_scene(CLI::App& simulate, const Options& o, SimulateRequest& request) {
  const Scene scene =
      apply_scene_file(simulate, o.scene_path, o.simulate.setup.params, request.setup);
  request.scene_path = o.scene_path;
  request.scene_dt_s = scene.sample_rate_hz ? 1.0 / *scene.sample_rate_hz : 0.0;
}

int run_simulate(CLI::App& simulate, Options& o, std::ostream& out) {
  SimulateRequest request = o.simulate;
  OscillatorParams& p = request.setup.params;
  const bool scene = !o.scene_path.empty();
  if (scene) apply_scene(simulate, o, request);
  const auto given = [&](const char* name) { return simulate.get_option(name)->count() > 0; };
  if (!scene && !given("--model")) throw UsageError("--model is required (or give a --scene)");
  if (scene && !given("--model")) {
    // the scene's model and integrator stand unless flags change them
  } else if (!parse_model(o.model.c_str(), p.model)) {
    throw UsageError("--model: unknown model '" + o.model +
                     "' (expected linear, signum, smooth, stick-slip or stribeck)");
  }
  if ((!scene || given("--smoothing")) && !parse_smoothing(o.smoothing.c_str(), p.smoothing)) {
    throw UsageError("--smoothing: unknown form '" + o.smoothing +
                     "' (expected atan, tanh, erf or rational)");
  }
  if (o.integrator.empty()) {
    // Without --integrator: the scene's (if it kept its model), else the model's default.
    if (!scene || given("--model")) p.integrator = default_integrator(p.model);
  } else if (o.integrator == "reference") {
    request.setup.reference = true;  // host-only solver; the core's integrator is not used
    p.integrator = default_integrator(p.model);
  } else if (!parse_integrator(o.integrator.c_str(), p.integrator)) {
    // (The message predates 'reference'; tests/host/test_simulate_errors.cpp pins its text.)
    throw UsageError("--integrator: unknown integrator '" + o.integrator +
                     "' (expected euler, symplectic, rk4, exact or reference)");
  }
  if (!parse_scalar(o.scalar, request.scalar)) {
    throw UsageError("--scalar: unknown scalar '" + o.scalar +
                     "' (expected double, float, fixed or fixed32)");
  }
  if (!scene && !given("--ffs")) p.static_friction_n = p.kinetic_friction_n;
  const SimulateResult result = simulate_file(request);
  out << result.stats_json << "\n";  // the last line of stdout, for tools
  return kExitOk;
}

// One line, whatever the message holds.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err) {
  try {
    Options options;
    CLI::App app("stickslip: seat suspension with dry friction, simulated sample by sample",
                 "stickslip");
    app.require_subcommand(1);
    app.footer(
        "Exit status: 0 success, 1 bad input data or failed file operation, 2 command-line error.");
    add_generate(app, options);
    add_simulate(app, options);
    add_demo(app, options);
    add_replay(app, options);
    add_ecu(app, options);
    add_record(app, options);
    add_play(app, options);
    ExtraCommands extra;  // sweep, merge, psd, harmonic-balance, advise
    extra.add_to(app);
    // CLI11 would only say "A subcommand is required" for a misspelt one.
    const std::string first = argc >= 2 ? argv[1] : "";
    if (!first.empty() && first[0] != '-' && first != "generate" && first != "simulate" &&
        first != "demo" && first != "replay" && first != "ecu" && first != "record" &&
        first != "play" && !ExtraCommands::is_name(first)) {
      throw UsageError(std::string("unknown subcommand '") + argv[1] +
                       "' (expected generate, simulate, demo, replay, ecu, record, play, " +
                       ExtraCommands::names() + "; see stickslip --help)");
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
      if (error.get_exit_code() == 0) {  // --help
        out << app.help();
        return kExitOk;
      }
      err << "stickslip: " << one_line(error.what()) << "\n";
      return kExitUsage;
    }
    if (int status = 0; extra.run(app, out, err, status)) return status;
    if (app.got_subcommand("generate"))
      return run_generate(*app.get_subcommand("generate"), options, out);
    if (app.got_subcommand("simulate"))
      return run_simulate(*app.get_subcommand("simulate"), options, out);
    if (app.got_subcommand("replay"))
      return run_replay(*app.get_subcommand("replay"), options, out);
    if (app.got_subcommand("ecu")) return run_ecu_command(*app.get_subcommand("ecu"), options, out);
    if (app.got_subcommand("record")) return run_record(options, out);
    if (app.got_subcommand("play")) return run_play(options, out);
    run_demo(options.demo, out);
    return kExitOk;
  } catch (const UsageError& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitUsage;
  } catch (const HostError& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    err << "stickslip: out of memory\n";
    return kExitFailure;
  } catch (const std::exception& error) {
    err << "stickslip: " << one_line(error.what()) << "\n";
    return kExitFailure;
  } catch (...) {
    err << "stickslip: unexpected error\n";
    return kExitFailure;
  }
}

int run_cli(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  std::vector<std::string> storage;
  storage.reserve(arguments.size() + 1);
  storage.emplace_back("stickslip");
  storage.insert(storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& argument : storage) argv.push_back(argument.data());
  argv.push_back(nullptr);
  return run_cli(static_cast<int>(storage.size()), argv.data(), out, err);
}

}  // namespace stickslip::host
