// A scene names the effects it models; the model type is chosen from them once, outside the
// sample loop (with_scene_model), so the step contains exactly those effects and nothing is
// checked per sample for an effect the scene leaves out:
//   spring + damper                      -> Oscillator<T, NoFriction> (k, b in the affine map)
//   + coulomb                            -> Oscillator<T, SignumFriction> (or a smoothed law)
//   + static_friction                    -> Oscillator<T, CoulombStickSlip>
//   + stribeck                           -> Oscillator<T, StribeckStickSlip>
//   + end_stops (with none, stick-slip or stribeck)
//                                        -> EndStopOscillator<T, NoFriction / CoulombStickSlip /
//                                           StribeckStickSlip>
#pragma once

#include "stickslip/core/params.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/end_stops.hpp"

namespace stickslip {

enum SceneEffect : unsigned {
  kSpring = 1u << 0,
  kDamper = 1u << 1,
  kCoulomb = 1u << 2,         // kinetic (sliding) friction F_fk
  kStaticFriction = 1u << 3,  // sticking up to F_fs >= F_fk
  kStribeck = 1u << 4,        // velocity weakening between F_fs and F_fk
  kEndStops = 1u << 5,        // stroke limit: stiff, damped stops beyond +-travel
};

// The cheapest model with all the effects: linear, signum (Coulomb), stick-slip (+ static
// friction), stribeck (+ Stribeck).
constexpr FrictionModel model_for_effects(unsigned effects) noexcept {
  if ((effects & kCoulomb) == 0) return FrictionModel::linear;
  if (effects & kStribeck) return FrictionModel::stribeck;
  if (effects & kStaticFriction) return FrictionModel::stick_slip;
  return FrictionModel::signum;
}

struct SceneParams {
  unsigned effects = kSpring | kDamper;
  OscillatorParams seat;
  EndStopParams stops;  // used when effects has kEndStops
};

template <typename T, typename Law>
ConfigResult configure_for_scene(Oscillator<T, Law>& model, const SceneParams& scene) noexcept {
  return model.configure(scene.seat);
}
template <typename T, typename Law>
ConfigResult configure_for_scene(EndStopOscillator<T, Law>& model,
                                 const SceneParams& scene) noexcept {
  return model.configure(scene.seat, scene.stops);
}

// Calls fn(model) with a model of exactly the scene's effects (unconfigured: call
// configure_for_scene(model, scene)). With end stops the seat's model must be linear,
// stick-slip or stribeck (configure refuses the others with a message).
template <typename T, typename Fn>
decltype(auto) with_scene_model(const SceneParams& scene, Fn&& fn) {
  if (scene.effects & kEndStops) {
    if (scene.seat.model == FrictionModel::linear) {
      EndStopOscillator<T, NoFriction> model;
      return fn(model);
    }
    if (scene.seat.model == FrictionModel::stribeck) {
      EndStopOscillator<T, StribeckStickSlip> model;
      return fn(model);
    }
    EndStopOscillator<T, CoulombStickSlip> model;
    return fn(model);
  }
  return with_oscillator<T>(scene.seat, fn);
}

}  // namespace stickslip
