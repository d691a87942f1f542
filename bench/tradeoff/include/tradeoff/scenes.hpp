// The standard scenes of the speed-vs-accuracy harness and their inputs.
//
// A scene is an excitation (wideband, lorry-like, harmonic near resonance, RMS a0u = 0.35 m/s^2)
// and the physics of the seat: no friction (linear), Coulomb friction with F_fs = F_fk, or Stribeck
// friction with F_fs = 1.3 F_fk and v_S = 0.01 m/s; F_fk from Den Hartog's factor
// K = 4 F_fk / (pi sqrt(2) m a0u). The continuous signal is generated once at kBaseDtS; the input
// at a step dt is every (dt / kBaseDtS)-th sample of it, so every run at that dt and its reference
// see the same samples.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/signals/signal_generator.hpp"

namespace stickslip::tradeoff {

// 0.05 ms: every dt of the standard list (0.1, 0.25, 0.5, 1, 2, 5, 10 ms) is a whole multiple.
inline constexpr double kBaseDtS = 5e-5;
inline constexpr double kBaseDtMs = 0.05;

enum class SceneFriction : std::uint8_t { none, coulomb, stribeck };
const char* friction_name(SceneFriction friction) noexcept;

struct SceneOptions {
  std::vector<host::SignalKind> kinds{host::SignalKind::wideband, host::SignalKind::lorry,
                                      host::SignalKind::harmonic};
  std::vector<SceneFriction> frictions{SceneFriction::none, SceneFriction::coulomb,
                                       SceneFriction::stribeck};
  std::vector<double> den_hartog_ks{0.2, 0.8, 1.5};
  std::vector<double> dampings_ns_per_m{504.0, 0.0};
  double duration_s = 20.0;
  double rms_m_per_s2 = 0.35;
  double harmonic_hz = 1.8;                 // near the 1.82 Hz resonance of the reference system
  double stribeck_ratio = 1.3;              // F_fs / F_fk in Stribeck scenes
  double stribeck_velocity_m_per_s = 0.01;  // v_S
  std::uint64_t seed = 1;
};

struct Scene {
  std::string name;  // e.g. "lorry-K0.8-b504", "lorry-stribeck-K0.8-b0", "lorry-linear-b504"
  host::SignalKind kind = host::SignalKind::lorry;
  SceneFriction friction = SceneFriction::coulomb;
  double den_hartog_k = 0.0;  // 0 for frictionless scenes
  // The scene's physics: mass, spring, damper, F_fk, F_fs, v_S, and the model that is physically
  // right for it (linear, stick_slip or stribeck). dt_s and the integrator are set per run.
  OscillatorParams physics;
};

// Every combination of the options (frictionless scenes do not repeat over K).
std::vector<Scene> make_scenes(const SceneOptions& options);

// F_fk = K pi sqrt(2) m a0u / 4.
double kinetic_friction_for(double den_hartog_k, double mass_kg, double rms_m_per_s2) noexcept;

// The continuous signal of a kind at kBaseDtS over the options' duration (seed, RMS, frequency).
std::vector<double> generate_base_signal(host::SignalKind kind, const SceneOptions& options);

// dt / kBaseDtS; throws host::UsageError unless dt_ms is a positive whole multiple of 0.05 ms.
std::size_t stride_for_dt_ms(double dt_ms);

// base[0], base[stride], base[2 stride], ...
template <typename T>
std::vector<T> sample_every(const std::vector<double>& base, std::size_t stride) {
  std::vector<T> out;
  out.reserve(base.size() / stride + 1);
  for (std::size_t n = 0; n < base.size(); n += stride) out.push_back(static_cast<T>(base[n]));
  return out;
}

}  // namespace stickslip::tradeoff
