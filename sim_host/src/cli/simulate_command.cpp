// stickslip simulate: the model over a recording (simulate_file.hpp).
#include <ostream>

#include "command.hpp"
#include "model_options.hpp"
#include "recording_options.hpp"
#include "stage_progress.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/run/simulate_file.hpp"

namespace stickslip::host {
namespace {

class SimulateCommand : public Command {
 public:
  void add_options(Options& simulate) override {
    simulate
        .add_option("--input", request_.input_path,
                    "recording: CSV t,a_u, a logger's text, .mat, or a CAN log with --dbc")
        ->required();
    simulate.add_option("--output", request_.output_path, "CSV file to write")->required();
    simulate.add_option("--stats", request_.stats_path, "also write the statistics JSON here");
    model_.add_to(simulate, request_.setup,
                  "scene file (TOML, docs/scenes/): effects, seat, model, integrator, sample "
                  "rate; the flags below override it");
    simulate
        .add_option("--repetitions", request_.setup.repetitions,
                    "timed runs for ns_per_sample (default 5; 3 above 2e6 steps)")
        ->check(OptionCheck::at_least_one);
    simulate.add_flag("--progress", progress_,
                      "print each stage on stderr (on a terminal: the stage still running once "
                      "the run takes over 2 s)");
    recording_.add_to(simulate);
  }

  int run(Options& simulate, std::ostream& out, std::ostream& err) override {
    SimulateRequest request = request_;
    request.recording = recording_.resolve();
    const ResolvedModel model = model_.resolve(simulate, request.setup);
    request.scalar = model.scalar;
    // simulate_file() checks the scene's sample rate against the recording's (a --dt given
    // overrides it).
    request.scene_path = model.scene_path;
    request.scene_dt_s = model.scene_dt_s();
    SimulateResult result;
    {
      StageProgress progress(err, "simulate", progress_, stderr_is_terminal(err));
      request.on_stage = [&progress](const std::string& stage) { progress.begin(stage); };
      result = simulate_file(request);
    }
    print_recording_report(err, request.input_path, result.recording);
    out << result.stats_json << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  SimulateRequest request_;
  ModelOptions model_{kSimulateChoices};
  bool progress_ = false;
  RecordingOptionGroup recording_;
};

}  // namespace

std::unique_ptr<Command> make_simulate_command() {
  return std::make_unique<SimulateCommand>();
}

}  // namespace stickslip::host
