#include "model_options.hpp"

#include <fmt/format.h>

#include <vector>

#include "command.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/ecu_node.hpp"
#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

std::vector<std::string> integrator_choices(const ModelChoices& choices) {
  std::vector<std::string> names = {"euler", "symplectic", "rk4", "exact"};
  if (choices.reference_integrator) names.push_back("reference");
  return names;
}

std::vector<std::string> scalar_choices(const ModelChoices& choices) {
  std::vector<std::string> names = {"double", "float", "fixed"};
  if (choices.fixed32) names.push_back("fixed32");
  return names;
}

std::string integrator_help(const ModelChoices& choices) {
  std::string help = join_choices(integrator_choices(choices), " | ", " | ") +
                     " (default: exact for linear, signum, stick-slip; rk4 for smooth, stribeck";
  if (choices.reference_integrator)
    help += "; reference: the event-driven reference solver, double only";
  return help + ")";
}

std::string scalar_help(const ModelChoices& choices) {
  if (choices.double_only) return "double (this command runs its seat in double only)";
  const char* laws = "linear, signum, smooth rational, stick-slip; euler, symplectic, exact";
  if (!choices.fixed32) return fmt::format("double | float | fixed (fixed: Q23.40: {})", laws);
  return fmt::format(
      "double | float | fixed | fixed32 (fixed: Q23.40; fixed32: Q7.24 in scene units, as on the "
      "Cortex-M0+; both: {})",
      laws);
}

// The seat's numbers from the scene file, then every flag the command was given over them.
void apply_scene_file(const Options& command, const Scene& scene, SimulationSetup& setup) {
  const OscillatorParams& flags = setup.params;
  OscillatorParams merged = scene.params;
  if (given(command, "--mass")) merged.mass_kg = flags.mass_kg;
  if (given(command, "--stiffness")) merged.stiffness_n_per_m = flags.stiffness_n_per_m;
  if (given(command, "--damping")) merged.damping_ns_per_m = flags.damping_ns_per_m;
  if (given(command, "--ffk")) merged.kinetic_friction_n = flags.kinetic_friction_n;
  if (given(command, "--ffs")) merged.static_friction_n = flags.static_friction_n;
  if (given(command, "--stribeck-velocity"))
    merged.stribeck_velocity_m_per_s = flags.stribeck_velocity_m_per_s;
  if (given(command, "--smoothing-c"))
    merged.smoothing_constant_s_per_m = flags.smoothing_constant_s_per_m;
  if (given(command, "--input-range")) merged.input_range_m_per_s2 = flags.input_range_m_per_s2;
  if (given(command, "--displacement-range"))
    merged.displacement_range_m = flags.displacement_range_m;
  merged.dt_s = flags.dt_s;
  setup.params = merged;
  setup.effects = scene.effects;
  setup.stops = scene.stops;
}

// The bus commands run the frame layout of docs/can/stickslip.dbc: a scene that names other
// identifiers is refused rather than silently ignored.
void check_scene_for_bus_node(const Scene& scene, const std::string& path) {
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
}

}  // namespace

void add_seat_options(Options& command, double& mass_kg, double& stiffness_n_per_m) {
  command.add_option("--mass", mass_kg, "seat mass m, kg")->capture_default_str();
  command.add_option("--stiffness", stiffness_n_per_m, "spring k, N/m")->capture_default_str();
}

void add_friction_options(Options& command, OscillatorParams& params, bool ffk_required) {
  Option* ffk = command.add_option("--ffk", params.kinetic_friction_n, "kinetic friction F_fk, N");
  if (ffk_required) {
    ffk->required();
  } else {
    ffk->capture_default_str();
  }
  command.add_option("--ffs", params.static_friction_n, "static friction F_fs, N (default: F_fk)");
}

void default_static_friction(const Options& command, OscillatorParams& params, const Scene* scene) {
  const bool scene_names_it = scene != nullptr && (scene->effects & kStaticFriction) != 0;
  if (!given(command, "--ffs") && !scene_names_it)
    params.static_friction_n = params.kinetic_friction_n;
}

void ModelOptions::add_to(Options& command, SimulationSetup& setup, const std::string& scene_help) {
  OscillatorParams& p = setup.params;
  command.add_option("--scene", scene_, scene_help);
  command.add_option("--model", model_,
                     "linear | signum | smooth | stick-slip | stribeck (required without --scene)");
  add_seat_options(command, p.mass_kg, p.stiffness_n_per_m);
  command.add_option("--damping", p.damping_ns_per_m, "damper b, N s/m")->capture_default_str();
  add_friction_options(command, p, false);
  command.add_option("--stribeck-velocity", p.stribeck_velocity_m_per_s, "v_S, m/s (stribeck)")
      ->capture_default_str();
  command.add_option("--smoothing", smoothing_, "atan | tanh | erf | rational (smooth)")
      ->capture_default_str();
  command.add_option("--smoothing-c", p.smoothing_constant_s_per_m, "c in s(c v_r), s/m (smooth)")
      ->capture_default_str();
  command.add_option("--integrator", integrator_, integrator_help(choices_));
  command.add_option("--scalar", scalar_, scalar_help(choices_))->capture_default_str();
  command
      .add_option("--input-range", p.input_range_m_per_s2,
                  "fixed point: largest |a_u| its scaling must hold, m/s^2")
      ->capture_default_str();
  command
      .add_option("--displacement-range", p.displacement_range_m,
                  "fixed point: largest |x_r| its scaling must hold, m")
      ->capture_default_str();
  command.add_option("--x0", setup.x0_m, "initial x_r, m")->capture_default_str();
  command.add_option("--v0", setup.v0_m_per_s, "initial v_r, m/s")->capture_default_str();
}

// Every name checked against its list before any file (the scene) is read.
void ModelOptions::check_names(const Options& command) const {
  OscillatorParams p;
  ScalarType scalar = ScalarType::float64;
  if (given(command, "--model") && !parse_model(model_.c_str(), p.model)) {
    throw UsageError(
        "--model: unknown model '" + model_ +
        "' (expected linear, signum, smooth, stick-slip or stribeck" +
        did_you_mean(model_, {"linear", "signum", "smooth", "stick-slip", "stribeck"}) + ")");
  }
  if (!parse_smoothing(smoothing_.c_str(), p.smoothing)) {
    throw UsageError("--smoothing: unknown form '" + smoothing_ +
                     "' (expected atan, tanh, erf or rational" +
                     did_you_mean(smoothing_, {"atan", "tanh", "erf", "rational"}) + ")");
  }
  const bool reference = choices_.reference_integrator && integrator_ == "reference";
  if (!integrator_.empty() && !reference && !parse_integrator(integrator_.c_str(), p.integrator)) {
    const std::vector<std::string> names = integrator_choices(choices_);
    throw UsageError("--integrator: unknown integrator '" + integrator_ + "' (expected " +
                     join_choices(names, ", ", " or ") + did_you_mean(integrator_, names) + ")");
  }
  if (!parse_scalar(scalar_, scalar)) {
    const std::vector<std::string> names = scalar_choices(choices_);
    throw UsageError("--scalar: unknown scalar '" + scalar_ + "' (expected " +
                     join_choices(names, ", ", " or ") + did_you_mean(scalar_, names) + ")");
  }
}

ResolvedModel ModelOptions::resolve(const Options& command, SimulationSetup& setup) const {
  check_names(command);
  ResolvedModel resolved;
  OscillatorParams& p = setup.params;
  const bool scene = !scene_.empty();
  if (scene) {
    resolved.scene_path = scene_;
    resolved.scene = read_scene_file(scene_);
    apply_scene_file(command, *resolved.scene, setup);
    if (choices_.bus_node) check_scene_for_bus_node(*resolved.scene, scene_);
  }
  const bool model_given = given(command, "--model");
  if (!scene && !model_given) throw UsageError("--model is required (or give a --scene)");
  if (model_given) parse_model(model_.c_str(), p.model);  // the name was checked above
  if (!scene || given(command, "--smoothing")) parse_smoothing(smoothing_.c_str(), p.smoothing);
  bool integrator_defaulted = false;
  if (integrator_.empty()) {
    // The scene's integrator stands while the scene's model does; else the model's default.
    integrator_defaulted = !scene || model_given;
    // The seat with end stops runs the exact integrator only (models/end_stops.hpp), whatever
    // the model's default elsewhere (rk4 for stribeck).
    const bool end_stops = scene && (resolved.scene->effects & kEndStops) != 0;
    if (integrator_defaulted)
      p.integrator = end_stops ? Integrator::exact : default_integrator(p.model);
  } else if (choices_.reference_integrator && integrator_ == "reference") {
    setup.reference = true;  // host-only solver; the core's integrator is not used
    p.integrator = default_integrator(p.model);
  } else {
    parse_integrator(integrator_.c_str(), p.integrator);
  }
  parse_scalar(scalar_, resolved.scalar);
  const bool fixed_point =
      resolved.scalar == ScalarType::fixed || resolved.scalar == ScalarType::fixed32;
  if (fixed_point && integrator_defaulted && p.integrator == Integrator::rk4 &&
      p.model == FrictionModel::smooth && p.smoothing == SmoothingLaw::rational) {
    // Only the integrator stands in the way, and it came from the model's default: naming
    // --integrator alone would blame a flag never given.
    throw UsageError("--scalar " + scalar_ + ": the default integrator of --model " +
                     model_name(p.model) +
                     " is rk4, which fixed point does not offer; give --integrator exact, "
                     "symplectic or euler");
  }
  default_static_friction(command, p, resolved.scene ? &*resolved.scene : nullptr);
  return resolved;
}

}  // namespace stickslip::host
