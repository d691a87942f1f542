// The keyword arguments of simulate(), Oscillator and Observer, resolved as `stickslip simulate`
// resolves its flags: the scene file first, then every argument given over it.
#include <cmath>
#include <optional>
#include <string>

#include "module.hpp"
#include "stickslip/host/io/scene_file.hpp"

namespace stickslip::python {
namespace {

const char* const kOptionNames[] = {"model",
                                    "mass",
                                    "stiffness",
                                    "damping",
                                    "ffk",
                                    "ffs",
                                    "stribeck_velocity",
                                    "smoothing",
                                    "smoothing_c",
                                    "integrator",
                                    "scalar",
                                    "input_range",
                                    "displacement_range",
                                    "x0",
                                    "v0",
                                    "scene",
                                    "repetitions"};

// The argument that sets each OscillatorParams field, to point the user at what to change.
const char* argument_for(const std::string& parameter) {
  static const struct {
    const char* parameter;
    const char* argument;
  } table[] = {{"mass_kg", "mass"},
               {"stiffness_n_per_m", "stiffness"},
               {"damping_ns_per_m", "damping"},
               {"kinetic_friction_n", "ffk"},
               {"static_friction_n", "ffs"},
               {"stribeck_velocity_m_per_s", "stribeck_velocity"},
               {"smoothing_constant_s_per_m", "smoothing_c"},
               {"model", "model"},
               {"smoothing", "smoothing"},
               {"input_range_m_per_s2", "input_range"},
               {"displacement_range_m", "displacement_range"},
               {"integrator", "integrator"},
               {"dt_s", "dt"},
               {"window_s", "window_s"},
               {"exponential_time_s", "exponential_time_s"},
               {"regime_hysteresis_k", "regime_hysteresis_k"},
               {"mismatch_rms_m_per_s2", "mismatch_rms"}};
  for (const auto& entry : table)
    if (parameter == entry.parameter) return entry.argument;
  return nullptr;
}

}  // namespace

// "mass: mass_kg: must be >= 1e-06 ..." from the core's "mass_kg: must be >= 1e-06 ...".
std::string explain_configuration_error(const std::string& core_message) {
  const std::string parameter = core_message.substr(0, core_message.find(' '));
  const std::string name = parameter.substr(0, parameter.find(':'));
  if (const char* argument = argument_for(name)) return std::string(argument) + ": " + core_message;
  return "invalid parameters: " + core_message;
}

namespace {

std::optional<double> optional_number(const py::dict& options, const char* key) {
  if (!options.contains(key) || options[key].is_none()) return std::nullopt;
  try {
    return options[key].cast<double>();
  } catch (const py::cast_error&) {
    throw HostError(std::string(key) + ": expected a number, got " +
                    py::repr(options[key]).cast<std::string>());
  }
}

std::optional<std::string> optional_text(const py::dict& options, const char* key) {
  if (!options.contains(key) || options[key].is_none()) return std::nullopt;
  py::object value = options[key];
  if (std::strcmp(key, "scene") == 0) value = py::module_::import("os").attr("fspath")(value);
  if (!py::isinstance<py::str>(value)) {
    throw HostError(std::string(key) + ": expected a string, got " +
                    py::repr(value).cast<std::string>());
  }
  return value.cast<std::string>();
}

void require_finite(const char* argument, double value) {
  if (!std::isfinite(value)) {
    throw HostError(std::string(argument) + ": must be a finite number, got " +
                    format_number(value));
  }
}
}  // namespace

RunSpec parse_spec(const py::dict& options) {
  for (const auto& item : options) {
    const std::string key = py::str(item.first);
    bool known = false;
    for (const char* name : kOptionNames) known = known || key == name;
    if (!known) {
      std::string expected;
      for (const char* name : kOptionNames)
        expected += (expected.empty() ? "" : ", ") + std::string(name);
      throw HostError("unknown parameter '" + key + "' (expected " + expected + ")");
    }
  }
  RunSpec spec;
  SimulationSetup& setup = spec.setup;
  OscillatorParams& p = setup.params;
  const std::optional<std::string> scene_path = optional_text(options, "scene");
  const bool scene = scene_path.has_value();
  if (scene) {
    const host::Scene file = host::read_scene_file(*scene_path);
    p = file.params;
    setup.effects = file.effects;
    setup.stops = file.stops;
    spec.scene_path = *scene_path;
    spec.scene_dt_s = file.sample_rate_hz ? 1.0 / *file.sample_rate_hz : 0.0;
  }
  const auto number = [&](const char* key, double& field) {
    if (const auto value = optional_number(options, key)) field = *value;
  };
  number("mass", p.mass_kg);
  number("stiffness", p.stiffness_n_per_m);
  number("damping", p.damping_ns_per_m);
  number("ffk", p.kinetic_friction_n);
  number("ffs", p.static_friction_n);
  number("stribeck_velocity", p.stribeck_velocity_m_per_s);
  number("smoothing_c", p.smoothing_constant_s_per_m);
  number("input_range", p.input_range_m_per_s2);
  number("displacement_range", p.displacement_range_m);
  const bool ffk_given = optional_number(options, "ffk").has_value();
  const bool ffs_given = optional_number(options, "ffs").has_value();
  // F_fs defaults to F_fk, unless the scene models static friction of its own.
  if (!ffs_given && (!scene || (ffk_given && !(setup.effects & kStaticFriction)))) {
    p.static_friction_n = p.kinetic_friction_n;
  }

  const std::optional<std::string> model = optional_text(options, "model");
  if (model && !parse_model(model->c_str(), p.model)) {
    throw HostError("model: unknown model '" + *model +
                    "' (expected linear, signum, smooth, stick-slip or stribeck)");
  }
  if (const auto smoothing = optional_text(options, "smoothing")) {
    if (!parse_smoothing(smoothing->c_str(), p.smoothing)) {
      throw HostError("smoothing: unknown form '" + *smoothing +
                      "' (expected atan, tanh, erf or rational)");
    }
  }
  const std::optional<std::string> integrator = optional_text(options, "integrator");
  if (!integrator) {
    // The scene's integrator stands if the scene keeps its model; else the model's default.
    if (!scene || model) p.integrator = default_integrator(p.model);
  } else if (*integrator == "reference") {
    setup.reference = true;
    p.integrator = default_integrator(p.model);
  } else if (!parse_integrator(integrator->c_str(), p.integrator)) {
    throw HostError("integrator: unknown integrator '" + *integrator +
                    "' (expected euler, symplectic, rk4, exact or reference)");
  }
  const std::string scalar = optional_text(options, "scalar").value_or("double");
  if (!host::parse_scalar(scalar, spec.scalar)) {
    throw HostError("scalar: unknown scalar '" + scalar +
                    "' (expected double, float, fixed or fixed32)");
  }
  number("x0", setup.x0_m);
  number("v0", setup.v0_m_per_s);
  require_finite("x0", setup.x0_m);
  require_finite("v0", setup.v0_m_per_s);
  // One run by default: an analyst wants the results; the command's 5 timed runs are for
  // ns_per_sample.
  setup.repetitions = 1;
  if (options.contains("repetitions") && !options["repetitions"].is_none()) {
    setup.repetitions = options["repetitions"].cast<int>();
    if (setup.repetitions < 1) {
      throw HostError("repetitions: must be >= 1, got " + std::to_string(setup.repetitions));
    }
  }
  if (setup.reference && spec.scalar != ScalarType::float64) {
    throw HostError(std::string("scalar '") + host::scalar_name(spec.scalar) +
                    "': the reference integrator runs in double only; use scalar='double'");
  }
  return spec;
}

}  // namespace stickslip::python
