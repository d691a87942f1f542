// The model options of the command line, declared once: --scene, --model, the seat, the friction
// law, --integrator, --scalar, the fixed-point ranges and the initial state (simulate, replay,
// ecu), and the seat and friction options sweep and advise share with them. What a command can
// run is its ModelChoices: its help lists only those, and anything else is refused when the
// options are resolved, naming the choice. Private to the host library.
#pragma once

#include "options.hpp"

#include <optional>
#include <string>

#include "stickslip/core/params.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

struct ModelChoices {
  bool reference_integrator = false;  // --integrator reference: the host-only reference solver
  bool fixed32 = false;               // --scalar fixed32: Q7.24 in scene units
  // The ECU node runs the scene: its CAN ids must be this build's frame layout and it may not
  // have end stops.
  bool bus_node = false;
  // The command runs its seat in double only and refuses the other scalars itself (closed-loop,
  // plant, controller): its help offers no other.
  bool double_only = false;
};

// simulate runs everything; the ECU node (replay, ecu) the core's integrators in double, float,
// Q23.40 and Q7.24 (the Cortex-M0+ firmware's seat, without end stops).
inline constexpr ModelChoices kSimulateChoices{true, true, false};
inline constexpr ModelChoices kBusNodeChoices{false, true, true};

struct ResolvedModel {
  ScalarType scalar = ScalarType::float64;
  std::string scene_path;      // empty: no --scene
  std::optional<Scene> scene;  // --scene, as read (the flags are applied over it in the setup)

  // The scene's sample interval; 0 when there is no scene or it names no sample rate.
  double scene_dt_s() const {
    return scene && scene->sample_rate_hz ? 1.0 / *scene->sample_rate_hz : 0.0;
  }
};

class ModelOptions {
 public:
  explicit ModelOptions(ModelChoices choices) : choices_(choices) {}

  // Declares the options; the numbers go straight into `setup` (read again by resolve()).
  void add_to(Options& command, SimulationSetup& setup, const std::string& scene_help);
  // The scene (if any) with the given flags over it, then the model, smoothing, integrator,
  // scalar and F_fs into `setup`. Throws UsageError naming the option.
  ResolvedModel resolve(const Options& command, SimulationSetup& setup) const;

 private:
  void check_names(const Options& command) const;

  ModelChoices choices_;
  std::string scene_;
  std::string model_;
  std::string integrator_;
  std::string smoothing_ = "tanh";
  std::string scalar_ = "double";
};

// --mass, --stiffness.
void add_seat_options(Options& command, double& mass_kg, double& stiffness_n_per_m);
// --ffk (required or with its default), --ffs (default: F_fk, see default_static_friction).
void add_friction_options(Options& command, OscillatorParams& params, bool ffk_required);
// F_fs defaults to F_fk: without --ffs, F_fs is F_fk unless the scene has the static_friction
// effect (then the scene's F_fs stands).
void default_static_friction(const Options& command, OscillatorParams& params, const Scene* scene);

}  // namespace stickslip::host
