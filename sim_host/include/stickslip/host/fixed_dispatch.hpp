// The oscillators the fixed-point scalar offers, chosen once from the parameters (host side:
// simulate --scalar fixed and the ECU node).
#pragma once

#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip::host {

// The oscillators fixed point offers (no transcendental functions); any other model goes to the
// stick-slip oscillator, whose configure() refuses it by name.
template <typename Fn>
inline decltype(auto) with_fixed_oscillator(const OscillatorParams& params, Fn&& fn) {
  switch (params.model) {
    case FrictionModel::linear: {
      Oscillator<Fixed, NoFriction> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::signum: {
      Oscillator<Fixed, SignumFriction> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::smooth: {
      Oscillator<Fixed, SmoothFriction<SmoothingLaw::rational>> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::stick_slip:
    case FrictionModel::stribeck:
    default: {
      Oscillator<Fixed, CoulombStickSlip> oscillator;
      return fn(oscillator);
    }
  }
}

}  // namespace stickslip::host
