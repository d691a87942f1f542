// The oscillators the fixed-point scalar offers, chosen once from the parameters (host side:
// simulate --scalar fixed and the ECU node).
#pragma once

#include <utility>

#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::host {

// The laws fixed point offers (no transcendental functions), as Seat<Law>: any other model goes
// to the stick-slip one, whose configure() refuses it by name.
template <template <typename> class Seat, typename Fn>
inline decltype(auto) with_fixed_law(const OscillatorParams& params, Fn&& fn) {
  switch (params.model) {
    case FrictionModel::linear: {
      Seat<NoFriction> seat;
      return fn(seat);
    }
    case FrictionModel::signum: {
      Seat<SignumFriction> seat;
      return fn(seat);
    }
    case FrictionModel::smooth: {
      Seat<SmoothFriction<SmoothingLaw::rational>> seat;
      return fn(seat);
    }
    case FrictionModel::stick_slip:
    case FrictionModel::stribeck:
    default: {
      Seat<CoulombStickSlip> seat;
      return fn(seat);
    }
  }
}

template <typename Law>
using FixedSeat = Oscillator<Fixed, Law>;

// Q23.40 (simulate --scalar fixed and the ECU node).
template <typename Fn>
inline decltype(auto) with_fixed_oscillator(const OscillatorParams& params, Fn&& fn) {
  return with_fixed_law<FixedSeat>(params, std::forward<Fn>(fn));
}

// Q23.40 with the scene's effects: with end stops the end-stop model (no friction, or Coulomb
// stick-slip, whose configure() refuses any other model by name), else with_fixed_oscillator's.
// Configure the model with configure_for_scene().
template <typename Fn>
inline decltype(auto) with_fixed_scene_model(const SceneParams& scene, Fn&& fn) {
  if (scene.effects & kEndStops) {
    if (scene.seat.model == FrictionModel::linear) {
      EndStopOscillator<Fixed, NoFriction> model;
      return fn(model);
    }
    EndStopOscillator<Fixed, CoulombStickSlip> model;
    return fn(model);
  }
  return with_fixed_oscillator(scene.seat, std::forward<Fn>(fn));
}

}  // namespace stickslip::host
