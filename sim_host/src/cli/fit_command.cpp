// stickslip fit: identifies the seat from a rig recording (run/fit.hpp).
#include <fmt/format.h>

#include <cmath>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command.hpp"
#include "recording_options.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/fit.hpp"
#include "stickslip/host/run/fit_report.hpp"
#include "stickslip/host/run/rig_source.hpp"

namespace stickslip::host {
namespace {

const std::vector<std::string> kModels = {"stick-slip", "stribeck", "linear", "signum"};
const char* const kParameterList = "mass, stiffness, damping, ffk, ffs, stribeck-velocity";

FitParameter parameter_named(const char* option, const std::string& name) {
  FitParameter parameter{};
  if (!parse_fit_parameter(name, parameter)) {
    throw UsageError(
        fmt::format("{}: unknown parameter '{}' (expected {})", option, name, kParameterList));
  }
  return parameter;
}

// "NAME=VALUE" entries into `values` (SI units, > 0).
void parse_assignments(const char* option, const std::vector<std::string>& entries,
                       std::array<double, kFitParameterCount>& values) {
  for (const std::string& entry : entries) {
    const std::size_t equals = entry.find('=');
    if (equals == std::string::npos)
      throw UsageError(fmt::format("{}: expected NAME=VALUE, got '{}'", option, entry));
    const FitParameter parameter = parameter_named(option, entry.substr(0, equals));
    double value = 0.0;
    try {
      std::size_t used = 0;
      value = std::stod(entry.substr(equals + 1), &used);
      if (used != entry.size() - equals - 1) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw UsageError(fmt::format("{}: '{}' is no number", option, entry.substr(equals + 1)));
    }
    if (!(value > 0.0) || !std::isfinite(value))
      throw UsageError(fmt::format("{}: {} must be a positive number", option, entry));
    values[static_cast<std::size_t>(parameter)] = value;
  }
}

std::vector<std::string> default_fit(FrictionModel model) {
  switch (model) {
    case FrictionModel::linear:
      return {"stiffness", "damping"};
    case FrictionModel::signum:
      return {"stiffness", "damping", "ffk"};
    case FrictionModel::stribeck:
      return {"stiffness", "damping", "ffk", "ffs", "stribeck-velocity"};
    default:
      return {"stiffness", "damping", "ffk", "ffs"};
  }
}

class FitCommand : public Command {
 public:
  void add_options(Options& fit) override {
    fit.add_option("--input", input_,
                   "rig recording: columns t (s), a_u and a_x (m/s^2), optionally x_r (m); or "
                   "any text or CAN log the readers accept, its channels named by the options "
                   "under Recording")
        ->required();
    fit.add_option("--model", model_, "stick-slip | stribeck | linear | signum")
        ->default_str("stick-slip");
    fit.add_option("--mass", request_.mass_kg,
                   "the seat's mass, kg (a_u, a_x and x_r fix only k/m, b/m and F/m)")
        ->check(OptionCheck::positive);
    fit.add_option("--fit", fit_,
                   "parameters to estimate, comma-separated: stiffness, damping, ffk, ffs, "
                   "stribeck-velocity (default: all the model has)")
        ->delimiter(',');
    fit.add_option("--start", start_,
                   "NAME=VALUE (SI): start of a fitted parameter, or the value of one not fitted "
                   "(default: from the data)");
    fit.add_option("--lower", lower_, "NAME=VALUE (SI): lower bound of a fitted parameter");
    fit.add_option("--upper", upper_, "NAME=VALUE (SI): upper bound of a fitted parameter");
    fit.add_option("--travel-noise", request_.travel_noise_m,
                   "RMS noise of x_r, m: weighs the travel residual against a_x's (default 1e-4)")
        ->check(OptionCheck::positive);
    fit.add_option("--max-iterations", request_.max_iterations,
                   "Levenberg-Marquardt iterations before the fit gives up (default 100)")
        ->check(OptionCheck::at_least_one);
    fit.add_option("--plot", plot_, "write the a_x residual against t as a PNG here (gnuplot)");
    recording_.add_to(fit);
    fit.add_option("--ax-signal", rig_options_.ax_signal,
                   "the seat acceleration a_x: column name or 1-based index (default a_x); CAN "
                   "log: MESSAGE.SIGNAL with --dbc")
        ->group("Recording");
    fit.add_option("--ax-unit", rig_options_.ax_unit,
                   "g | m/s^2 | mm/s^2: a_x's unit over the header's or DBC's")
        ->group("Recording");
    fit.add_option("--travel-signal", rig_options_.travel_signal,
                   "the seat travel x_r: column name or index (default: a column x_r if there "
                   "is one); CAN log: MESSAGE.SIGNAL")
        ->group("Recording");
    fit.add_option("--travel-unit", rig_options_.travel_unit,
                   "m | mm | cm | um: x_r's unit over the header's or DBC's")
        ->group("Recording");
  }

  int run(Options&, std::ostream& out, std::ostream& err) override {
    FitRequest request = request_;
    if (!parse_model(model_.c_str(), request.model) || !is_fit_model(model_)) {
      throw UsageError(fmt::format("--model: unknown model '{}' (expected {}{})", model_,
                                   join_choices(kModels, ", ", " or "),
                                   did_you_mean(model_, kModels)));
    }
    for (const std::string& name : fit_.empty() ? default_fit(request.model) : fit_)
      request.fit[static_cast<std::size_t>(parameter_named("--fit", name))] = true;
    parse_assignments("--start", start_, request.start);
    parse_assignments("--lower", lower_, request.lower);
    parse_assignments("--upper", upper_, request.upper);
    apply_fixed_values(request);
    if (!plot_.empty() && plot_.find_first_of("'\"") != std::string::npos)
      throw UsageError("--plot: the file name must not contain quotes");
    if (!plot_.empty() && !gnuplot_available())
      throw HostError("--plot: gnuplot is not installed (tools/install-deps.sh --report)");
    RigSourceOptions rig_options = rig_options_;
    rig_options.recording = recording_.resolve();
    check_unit("--ax-unit", rig_options.ax_unit, Quantity::acceleration);
    check_unit("--travel-unit", rig_options.travel_unit, Quantity::length);
    const RigSource source = read_rig_source(input_, rig_options);
    const RigRecording& rig = source.rig;
    print_recording_report(err, input_, source.a_u);
    print_recording_report(err, input_, source.a_x);
    if (rig.has_travel()) print_recording_report(err, input_, source.x_r);
    const FitResult result = fit_seat(rig, request);
    if (!result.converged) {
      err << fmt::format(
          "stickslip: {}: the fit did not converge after {} iterations ({}); no estimates\n",
          input_, result.iterations, result.solver_message);
      return kExitFailure;
    }
    if (!plot_.empty()) write_residual_plot(rig, result, plot_);
    out << fit_report_text(result);
    out << fit_json(result) << "\n";  // the last line of stdout, for tools
    return kExitOk;
  }

 private:
  static bool is_fit_model(const std::string& name) {
    for (const std::string& model : kModels)
      if (name == model) return true;
    return false;
  }

  static void check_unit(const char* option, const std::string& unit, Quantity quantity) {
    double factor = 0.0;
    if (!unit.empty() && !unit_factor(quantity, unit, factor)) {
      throw UsageError(
          fmt::format("{}: '{}' is not {}", option, unit,
                      quantity == Quantity::length ? "m, mm, cm or um" : "g, m/s^2 or mm/s^2"));
    }
  }

  // --start of a parameter not fitted sets its value (F_fs of a signum fit is unused).
  static void apply_fixed_values(FitRequest& request) {
    const auto& start = request.start;
    OscillatorParams& fixed = request.fixed;
    if (start[1] > 0.0) fixed.stiffness_n_per_m = start[1];
    if (start[2] > 0.0) fixed.damping_ns_per_m = start[2];
    if (start[3] > 0.0) fixed.kinetic_friction_n = start[3];
    if (start[4] > 0.0) fixed.static_friction_n = start[4];
    if (start[5] > 0.0) fixed.stribeck_velocity_m_per_s = start[5];
    if (fixed.static_friction_n < fixed.kinetic_friction_n)
      fixed.static_friction_n = fixed.kinetic_friction_n;
  }

  std::string input_, model_ = "stick-slip", plot_;
  std::vector<std::string> fit_, start_, lower_, upper_;
  FitRequest request_;
  RecordingOptionGroup recording_;
  RigSourceOptions rig_options_;
};

}  // namespace

std::unique_ptr<Command> make_fit_command() {
  return std::make_unique<FitCommand>();
}

}  // namespace stickslip::host
