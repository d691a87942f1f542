// stickslip closed-loop: the seat with an actuator and a controller over a recording
// (run/closed_loop.hpp; the per-sample loop is control/closed_loop.hpp).
#include <fmt/format.h>

#include <ostream>

#include "command.hpp"
#include "loop_options.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/run/closed_loop.hpp"

namespace stickslip::host {
namespace {

// The core's integrators in double: no reference solver, no fixed point (the state estimator
// has none), no bus ids.
inline constexpr ModelChoices kClosedLoopChoices{false, false, false, true};

class ClosedLoopCommand : public Command {
 public:
  void add_options(Options& command) override {
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
    model_.add_to(
        command, request_.setup.plant,
        "scene file (TOML, docs/scenes/), end stops included; the flags below override it");
    ClosedLoopSetup& s = request_.setup;
    controller_options_.add_to(command, s);
    command.add_option("--a-x-resolution", s.a_x_resolution_m_per_s2,
                       "seat accelerometer quantum, m/s^2 (default 0: none)");
    command.add_option("--x-r-resolution", s.x_r_resolution_m,
                       "travel sensor quantum, m (default 0: none)");
    command.add_option("--seed", s.seed, "seed of the sensor noise (default 1)");
    command.add_flag("--can-resolution", can_resolution_,
                     "quantise a_u, a_x, x_r and the force as the CAN frames between `stickslip "
                     "plant` and `stickslip controller` do (overrides --a-x-resolution and "
                     "--x-r-resolution): the in-process twin of the loop over a bus");
    command.add_option("--sweep-gain", sweep_,
                       "LO:HI:N: N runs with the hook gain from LO to HI (both included); "
                       "--output gets one row per gain");
    command.add_option("--plot", request_.plot_path,
                       "with --sweep-gain: the Pareto plot (seat weighted RMS against actuator "
                       "force RMS) as a PNG here (gnuplot)");
    recording_.add_to(command);
  }

  int run(Options& command, std::ostream& out, std::ostream& err) override {
    ClosedLoopRequest request = request_;
    request.recording = recording_.resolve();
    const ResolvedModel model = model_.resolve(command, request.setup.plant);
    if (model.scalar != ScalarType::float64) {
      throw UsageError(fmt::format(
          "--scalar {}: closed-loop runs its seat, state estimator and controller in double",
          scalar_name(model.scalar)));
    }
    request.scene_path = model.scene_path;
    request.scene_dt_s = model.scene_dt_s();
    controller_options_.resolve(command, request.setup);
    if (can_resolution_) set_can_resolution(request.setup);
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
  LoopControllerOptions controller_options_;
  std::string sweep_;
  bool can_resolution_ = false;
};

}  // namespace

std::unique_ptr<Command> make_closed_loop_command() {
  return std::make_unique<ClosedLoopCommand>();
}

}  // namespace stickslip::host
