// Scene files (TOML): what a scene models (its effects), the seat's parameters, the model and
// integrator, the sample rate and the CAN ids, in one file the host tools share
// (`simulate --scene FILE`; command-line flags override what the file says). See
// docs/scenes/*.toml for examples.
//
//   [scene]   name, effects = ["spring", "damper", "coulomb", "static_friction", "stribeck"],
//             model (optional: derived from the effects), integrator, sample_rate_hz
//   [seat]    mass_kg, stiffness_n_per_m, damping_ns_per_m, kinetic_friction_n,
//             static_friction_n, stribeck_velocity_m_per_s, smoothing, smoothing_constant_s_per_m
//   [can]     input_id, output_id (11-bit identifiers)
//
// Strict: an unknown table or key, a wrong type, a parameter of an effect the scene leaves out,
// or an effect the core cannot model ("end_stops", for now) is an error naming file, line and key.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "stickslip/core/params.hpp"

namespace stickslip::host {

enum SceneEffect : unsigned {
  kSpring = 1u << 0,
  kDamper = 1u << 1,
  kCoulomb = 1u << 2,          // kinetic (sliding) friction F_fk
  kStaticFriction = 1u << 3,   // sticking up to F_fs >= F_fk
  kStribeck = 1u << 4,         // velocity-weakening between F_fs and F_fk
  kEndStops = 1u << 5,         // stroke limit (not modelled by the core yet: refused)
};

struct SceneCanIds {
  std::optional<std::uint32_t> input_id, output_id;
};

struct Scene {
  std::string name;
  unsigned effects = 0;             // SceneEffect bits
  OscillatorParams params;          // the seat; dt_s from sample_rate_hz when given
  std::optional<double> sample_rate_hz;
  bool model_given = false;         // [scene] model was in the file (else derived from effects)
  bool integrator_given = false;
  SceneCanIds can;
};

// The model a set of effects needs: linear (no friction), signum (Coulomb), stick-slip
// (Coulomb + static friction), stribeck (+ Stribeck).
FrictionModel model_for_effects(unsigned effects) noexcept;

// Reads and checks a scene file; throws HostError "FILE:LINE:COL: ..." on any problem.
Scene read_scene_file(const std::string& path);

}  // namespace stickslip::host
