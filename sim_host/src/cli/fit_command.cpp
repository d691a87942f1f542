// stickslip fit: identifies the seat from a rig recording (run/fit.hpp).
#include <fmt/format.h>

#include <cmath>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command.hpp"
#include "stickslip/host/cli/cli.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/fit.hpp"
#include "stickslip/host/run/fit_report.hpp"

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
  void add_options(CLI::App& fit) override {
    fit.add_option("--input", input_,
                   "rig recording with columns t (s), a_u and a_x (m/s^2), optionally x_r (m); "
                   "any delimited text the readers accept")
        ->required();
    fit.add_option("--model", model_, "stick-slip | stribeck | linear | signum")
        ->default_str("stick-slip");
    fit.add_option("--mass", request_.mass_kg,
                   "the seat's mass, kg (a_u, a_x and x_r fix only k/m, b/m and F/m)");
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
        ->check(CLI::PositiveNumber);
    fit.add_option("--max-iterations", request_.max_iterations,
                   "Levenberg-Marquardt iterations before the fit gives up (default 100)")
        ->check(at_least_one());
    fit.add_option("--plot", plot_, "write the a_x residual against t as a PNG here (gnuplot)");
  }

  int run(CLI::App&, std::ostream& out, std::ostream& err) override {
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
    const RigRecording rig = read_rig_recording(input_);
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
};

}  // namespace

std::unique_ptr<Command> make_fit_command() {
  return std::make_unique<FitCommand>();
}

}  // namespace stickslip::host
