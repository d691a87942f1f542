// stickslip plant and stickslip controller: the closed loop split over a CAN bus
// (bus/control_nodes.hpp, docs/CONTROL.md "The controller over CAN").
#include <fmt/format.h>

#include <ostream>

#include "command.hpp"
#include "loop_options.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/bus/control_nodes.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stop_signals.hpp"

namespace stickslip::host {
namespace {

// The core's integrators in double, as closed-loop.
inline constexpr ModelChoices kLoopNodeChoices{false, false, false, true};

void refuse_loopback(const std::string& bus, const char* node, const char* other) {
  if (bus != "loopback") return;
  // No other program can send on a bus that lives in this process.
  throw UsageError(fmt::format(
      "--bus loopback: {} would wait forever, as no other program can reach the in-process "
      "loopback bus; run {} and {} on a CAN interface such as vcan0",
      node, node, other));
}

class PlantCommand : public Command {
 public:
  void add_options(Options& command) override {
    command
        .add_option(
            "--input", request_.input_path,
            "cab-floor recording: CSV t,a_u, a logger's text, .mat, or a CAN log with --dbc")
        ->required();
    command
        .add_option("--output", request_.output_path,
                    "CSV to write: the trace t,a_u,x_r,v_r,a_x,f_f,stuck,f_a (as closed-loop's)")
        ->required();
    command.add_option("--stats", request_.stats_path, "also write the JSON line here");
    command.add_option("--bus", request_.bus, "CAN interface, e.g. vcan0")->required();
    model_.add_to(
        command, request_.setup.plant,
        "scene file (TOML, docs/scenes/), end stops included; the flags below override it");
    ClosedLoopSetup& s = request_.setup;
    add_sensor_noise_options(command, s);
    command.add_option("--seed", s.seed, "seed of the sensor noise (default 1)");
    command.add_option("--pace", pace_,
                       "max (lock-step: each answer awaited; default) | realtime (one sample "
                       "per dt on absolute deadlines)");
    command.add_option("--hold-frames", request_.hold_frames,
                       "missing answers bridged with the last force before failing safe to f_a = 0 "
                       "(default 3)");
    command.add_option("--command-timeout", request_.command_timeout_s,
                       "--pace max: how long to wait for each answer, s (default 0.5)");
    command.add_option("--connect-timeout", request_.connect_timeout_s,
                       "how long to wait for the answer to sample 0, s (default 5)");
    recording_.add_to(command);
  }

  int run(Options& command, std::ostream& out, std::ostream& err) override {
    check_bus_name("--bus", request_.bus);
    refuse_loopback(request_.bus, "plant", "controller");
    PlantNodeRequest request = request_;
    request.recording = recording_.resolve();
    const ResolvedModel model = model_.resolve(command, request.setup.plant);
    if (model.scalar != ScalarType::float64)
      throw UsageError(
          fmt::format("--scalar {}: the plant runs in double", scalar_name(model.scalar)));
    request.scene_path = model.scene_path;
    request.scene_dt_s = model.scene_dt_s();
    if (pace_ == "max") {
      request.pace = Pace::max;
    } else if (pace_ == "realtime") {
      request.pace = Pace::realtime;
    } else {
      throw UsageError("--pace " + pace_ + ": expected max or realtime");
    }
    const PlantNodeResult result = run_plant_node(request);
    print_recording_report(err, request.input_path, result.recording);
    if (!result.bus_message.empty()) err << result.bus_message << "\n";
    if (result.state == "failsafe") {
      err << fmt::format(
          "plant: no answers at the end: failing safe (f_a = 0) since sample {} ({} steps failed "
          "safe in all)\n",
          result.counters.last_failsafe_sample, result.counters.failsafe_frames);
    }
    if (request.pace == Pace::realtime) {
      const PacingReport& p = result.pacing;
      err << fmt::format(
          "plant: paced {} ticks at {:.6g} Hz: wake-up lateness median {:.1f} us, 99.9 % {:.1f} "
          "us, worst {:.1f} us; {} deadline misses\n",
          p.ticks, 1.0 / request_dt(result), p.lateness_median_s * 1e6, p.lateness_p999_s * 1e6,
          p.lateness_worst_s * 1e6, p.deadline_misses);
    }
    out << result.json << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  static double request_dt(const PlantNodeResult& result) { return result.dt_s; }
  PlantNodeRequest request_;
  ModelOptions model_{kLoopNodeChoices};
  RecordingOptionGroup recording_;
  std::string pace_ = "max";
};

class ControllerCommand : public Command {
 public:
  void add_options(Options& command) override {
    command.add_option("--bus", request_.bus, "CAN interface, e.g. vcan0")->required();
    model_.add_to(command, request_.setup.plant,
                  "scene file (TOML, docs/scenes/): the seat the observer assumes and dt");
    command.add_option("--dt", request_.setup.plant.params.dt_s,
                       "sample interval, s (default: the scene's, else 0.001)");
    controller_options_.add_to(command, request_.setup);
    command.add_option("--idle-exit", request_.idle_exit_s,
                       "exit this long after the last sample, s (default 2)");
    command.add_option("--first-sample-timeout", request_.first_sample_s,
                       "fail if no sample comes within this long, s (default 0: wait)");
    command.add_option("--drop-every", request_.drop_every,
                       "fault injection: leave every K-th answer unsent (default 0: none)");
    command.add_option("--stop-after", request_.stop_after_s,
                       "fault injection: stop answering from this sample time on, s");
  }

  int run(Options& command, std::ostream& out, std::ostream& err) override {
    check_bus_name("--bus", request_.bus);
    refuse_loopback(request_.bus, "controller", "plant");
    ControllerNodeRequest request = request_;
    const ResolvedModel model = model_.resolve(command, request.setup.plant);
    if (model.scalar != ScalarType::float64)
      throw UsageError(
          fmt::format("--scalar {}: the controller runs in double", scalar_name(model.scalar)));
    if (model.scene_dt_s() > 0.0 && !given(command, "--dt"))
      request.setup.plant.params.dt_s = model.scene_dt_s();
    controller_options_.resolve(command, request.setup);
    const StopOnSignals signals;
    request.stop_requested = [] { return stop_requested != 0; };
    request.listening = [&err, &request] {
      err << fmt::format("controller: answering samples on {} (SIGINT or SIGTERM stops)\n",
                         request.bus);
      err.flush();
    };
    const ControllerNodeResult result = run_controller_node(request);
    out << result.json << "\n";
    if (!result.bus_error.empty()) throw HostError(result.bus_error);
    return kExitOk;
  }

 private:
  ControllerNodeRequest request_;
  ModelOptions model_{kLoopNodeChoices};
  LoopControllerOptions controller_options_;
};

}  // namespace

std::unique_ptr<Command> make_plant_command() {
  return std::make_unique<PlantCommand>();
}

std::unique_ptr<Command> make_controller_command() {
  return std::make_unique<ControllerCommand>();
}

}  // namespace stickslip::host
