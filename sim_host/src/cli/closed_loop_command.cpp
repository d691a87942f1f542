// stickslip closed-loop: the seat with an actuator and a controller over a recording
// (run/closed_loop.hpp; the per-sample loop is control/closed_loop.hpp).
#include <fmt/format.h>

#include <ostream>

#include "command.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/run/closed_loop.hpp"

namespace stickslip::host {
namespace {

// The core's integrators in double: no reference solver, no fixed point (the state estimator
// has none), no bus ids.
inline constexpr ModelChoices kClosedLoopChoices{false, false, false};

class ClosedLoopCommand : public Command {
 public:
  void add_options(CLI::App& command) override {
    command
        .add_option("--input", request_.input_path,
                    "recording: CSV t,a_u, a logger's text, .mat, or a CAN log with --dbc")
        ->required();
    command
        .add_option("--output", request_.output_path,
                    "CSV to write: the trace t,a_u,x_r,v_r,a_x,f_f,stuck,f_a (with "
                    "--sweep-gain: one row per gain)")
        ->required();
    command.add_option("--stats", request_.stats_path, "also write the JSON line here");
    model_.add_to(command, request_.setup.plant,
                  "scene file (TOML, docs/scenes/) without end stops; the flags below override it");
    ClosedLoopSetup& s = request_.setup;
    command.add_option("--controller", controller_,
                       "passive | skyhook | groundhook | skyhook-semi | groundhook-semi | "
                       "friction-compensation (default passive)");
    command.add_option("--gain", s.gain_ns_per_m, "hook gain c, N s/m (default 1500)");
    command.add_option("--b-min", s.min_damping_ns_per_m,
                       "semi-active damper's least damping, N s/m (default 0)");
    command.add_option("--b-max", s.max_damping_ns_per_m,
                       "semi-active damper's most damping, N s/m (default 3000)");
    command.add_option("--friction-compensation", s.friction_compensation,
                       "fraction of the observer's friction estimate fed forward, in [0, 1] "
                       "(default 0; friction-compensation alone: 0.8)");
    command.add_option("--force-limit", s.force_limit_n, "actuator force limit, N (default 1000)");
    command.add_option("--actuator-lag", s.actuator_lag_s,
                       "actuator first-order lag time constant, s (default 0: ideal)");
    command.add_option("--observer", observer_,
                       "estimator (state estimator on the measured a_x, x_r; default) | ideal "
                       "(the controller reads the plant's own v_r and F_f)");
    command.add_option("--a-x-noise", s.a_x_noise_m_per_s2,
                       "seat accelerometer noise, RMS per sample, m/s^2 (default 0)");
    command.add_option("--x-r-noise", s.x_r_noise_m,
                       "travel sensor noise, RMS per sample, m (default 0)");
    command.add_option("--a-x-resolution", s.a_x_resolution_m_per_s2,
                       "seat accelerometer quantum, m/s^2 (default 0: none)");
    command.add_option("--x-r-resolution", s.x_r_resolution_m,
                       "travel sensor quantum, m (default 0: none)");
    command.add_option("--seed", s.seed, "seed of the sensor noise (default 1)");
    command.add_option("--sweep-gain", sweep_,
                       "LO:HI:N: N runs with the hook gain from LO to HI (both included); "
                       "--output gets one row per gain");
    command.add_option("--plot", request_.plot_path,
                       "with --sweep-gain: the Pareto plot (seat weighted RMS against actuator "
                       "force RMS) as a PNG here (gnuplot)");
    recording_.add_to(command);
  }

  int run(CLI::App& command, std::ostream& out, std::ostream& err) override {
    ClosedLoopRequest request = request_;
    request.recording = recording_.resolve();
    const ResolvedModel model = model_.resolve(command, request.setup.plant);
    if (model.scalar != ScalarType::float64) {
      throw UsageError(fmt::format(
          "--scalar {}: closed-loop runs in double (the state estimator has no fixed point)",
          scalar_name(model.scalar)));
    }
    request.scene_path = model.scene_path;
    request.scene_dt_s = model.scene_dt_s();
    if (!parse_controller(controller_, request.setup.controller)) {
      throw UsageError("--controller " + controller_ + ": expected " +
                       join_choices(controller_names(), ", ", " or ") +
                       did_you_mean(controller_, controller_names()));
    }
    if (observer_ == "estimator") {
      request.setup.observer = ObserverKind::estimator;
    } else if (observer_ == "ideal") {
      request.setup.observer = ObserverKind::ideal;
    } else {
      throw UsageError("--observer " + observer_ + ": expected estimator or ideal");
    }
    if (request.setup.controller == ControllerChoice::friction_compensation &&
        !given(command, "--friction-compensation")) {
      request.setup.friction_compensation = 0.8;
    }
    if (!sweep_.empty()) request.sweep = parse_gain_sweep(sweep_);
    const ClosedLoopResult result = closed_loop_file(request);
    print_recording_report(err, request.input_path, result.recording);
    out << result.sweep_rows;
    out << result.json << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  ClosedLoopRequest request_;
  ModelOptions model_{kClosedLoopChoices};
  RecordingOptionGroup recording_;
  std::string controller_ = "passive";
  std::string observer_ = "estimator";
  std::string sweep_;
};

}  // namespace

std::unique_ptr<Command> make_closed_loop_command() {
  return std::make_unique<ClosedLoopCommand>();
}

}  // namespace stickslip::host
