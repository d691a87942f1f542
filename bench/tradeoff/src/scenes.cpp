#include "tradeoff/scenes.hpp"

#include <cmath>

#include <fmt/format.h>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff {
namespace {

constexpr double kPi = 3.14159265358979323846;

// "0.8", "1.5", "504": short and exact for the values the scenes use.
std::string short_number(double value) {
  return fmt::format("{:g}", value);
}

}  // namespace

const char* friction_name(SceneFriction friction) noexcept {
  switch (friction) {
    case SceneFriction::none:
      return "none";
    case SceneFriction::coulomb:
      return "coulomb";
    case SceneFriction::stribeck:
      return "stribeck";
  }
  return "?";
}

double kinetic_friction_for(double den_hartog_k, double mass_kg, double rms_m_per_s2) noexcept {
  return den_hartog_k * kPi * std::sqrt(2.0) * mass_kg * rms_m_per_s2 / 4.0;
}

std::vector<Scene> make_scenes(const SceneOptions& options) {
  std::vector<Scene> scenes;
  for (const host::SignalKind kind : options.kinds) {
    for (const SceneFriction friction : options.frictions) {
      const std::vector<double> ks =
          friction == SceneFriction::none ? std::vector<double>{0.0} : options.den_hartog_ks;
      for (const double k : ks) {
        for (const double damping : options.dampings_ns_per_m) {
          Scene scene;
          scene.kind = kind;
          scene.friction = friction;
          scene.den_hartog_k = k;
          OscillatorParams& p = scene.physics;
          p.damping_ns_per_m = damping;
          p.integrator = Integrator::exact;
          const std::string b = "-b" + short_number(damping);
          const std::string kind_name = host::signal_kind_name(kind);
          switch (friction) {
            case SceneFriction::none:
              p.model = FrictionModel::linear;
              scene.name = kind_name + "-linear" + b;
              break;
            case SceneFriction::coulomb:
              p.model = FrictionModel::stick_slip;
              p.kinetic_friction_n = kinetic_friction_for(k, p.mass_kg, options.rms_m_per_s2);
              p.static_friction_n = p.kinetic_friction_n;
              scene.name = kind_name + "-K" + short_number(k) + b;
              break;
            case SceneFriction::stribeck:
              p.model = FrictionModel::stribeck;
              p.kinetic_friction_n = kinetic_friction_for(k, p.mass_kg, options.rms_m_per_s2);
              p.static_friction_n = options.stribeck_ratio * p.kinetic_friction_n;
              p.stribeck_velocity_m_per_s = options.stribeck_velocity_m_per_s;
              scene.name = kind_name + "-stribeck-K" + short_number(k) + b;
              break;
          }
          scenes.push_back(scene);
        }
      }
    }
  }
  return scenes;
}

std::vector<double> generate_base_signal(host::SignalKind kind, const SceneOptions& options) {
  host::GeneratorSpec spec;
  spec.kind = kind;
  spec.rms_m_per_s2 = options.rms_m_per_s2;
  spec.duration_s = options.duration_s;
  spec.dt_s = kBaseDtS;
  spec.seed = options.seed;
  spec.frequency_hz = options.harmonic_hz;
  return host::generate_signal(spec);
}

std::size_t stride_for_dt_ms(double dt_ms) {
  if (!(dt_ms > 0.0) || !std::isfinite(dt_ms)) {
    throw host::UsageError(
        fmt::format("dt {:g} ms: must be a positive number of milliseconds", dt_ms));
  }
  const double ratio = dt_ms / kBaseDtMs;
  const double whole = std::round(ratio);
  if (whole < 1.0 || std::fabs(ratio - whole) > 1e-9 * whole || whole > 1e8) {
    throw host::UsageError(
        fmt::format("dt {:g} ms: must be a whole multiple of the {:g} ms the input is generated at",
                    dt_ms, kBaseDtMs));
  }
  return static_cast<std::size_t>(whole);
}

}  // namespace stickslip::tradeoff
