// Scene files (TOML): what a scene models (its effects), the seat's parameters, the model and
// integrator, the sample rate and the CAN ids, in one file the host tools share
// (`simulate --scene FILE`; command-line flags override what the file says). See
// docs/scenes/*.toml for examples.
//
//   [scene]   name, effects = ["spring", "damper", "coulomb", "static_friction", "stribeck",
//             "end_stops"],
//             model (optional: derived from the effects), integrator, sample_rate_hz
//   [seat]    mass_kg, stiffness_n_per_m, damping_ns_per_m, kinetic_friction_n,
//             static_friction_n, stribeck_velocity_m_per_s, smoothing, smoothing_constant_s_per_m
//   [end_stops] travel_m, stiffness_n_per_m, damping_ns_per_m (needed with "end_stops")
//   [can]     input_id, output_id (11-bit identifiers)
//
// Strict: an unknown table or key, a wrong type, or a parameter of an effect the scene leaves out
// is an error naming file, line and key.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "stickslip/core/params.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::host {

struct SceneCanIds {
  std::optional<std::uint32_t> input_id, output_id;
};

struct Scene {
  std::string name;
  unsigned effects = 0;     // SceneEffect bits (models/scene.hpp)
  OscillatorParams params;  // the seat; dt_s from sample_rate_hz when given
  EndStopParams stops;      // [end_stops], when effects has kEndStops
  std::optional<double> sample_rate_hz;
  bool model_given = false;  // [scene] model was in the file (else derived from effects)
  bool integrator_given = false;
  SceneCanIds can;

  SceneParams core() const { return {effects, params, stops}; }
};

// Reads and checks a scene file; throws HostError "FILE:LINE:COL: ..." on any problem.
Scene read_scene_file(const std::string& path);

}  // namespace stickslip::host
