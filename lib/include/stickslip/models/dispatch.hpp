// Run-time model choice, resolved once outside the sample loop: calls fn(oscillator) with an
// oscillator instantiated for exactly the friction law the parameters name.
#pragma once

#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip {

template <typename T, typename Fn>
decltype(auto) with_oscillator(const OscillatorParams& params, Fn&& fn) {
  switch (params.model) {
    case FrictionModel::linear: {
      Oscillator<T, NoFriction> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::signum: {
      Oscillator<T, SignumFriction> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::smooth:
      switch (params.smoothing) {
        case SmoothingLaw::atan: {
          Oscillator<T, SmoothFriction<SmoothingLaw::atan>> oscillator;
          return fn(oscillator);
        }
        case SmoothingLaw::tanh: {
          Oscillator<T, SmoothFriction<SmoothingLaw::tanh>> oscillator;
          return fn(oscillator);
        }
        case SmoothingLaw::erf: {
          Oscillator<T, SmoothFriction<SmoothingLaw::erf>> oscillator;
          return fn(oscillator);
        }
        case SmoothingLaw::rational:
        default: {
          Oscillator<T, SmoothFriction<SmoothingLaw::rational>> oscillator;
          return fn(oscillator);
        }
      }
    case FrictionModel::stribeck: {
      Oscillator<T, StribeckStickSlip> oscillator;
      return fn(oscillator);
    }
    case FrictionModel::stick_slip:
    default: {
      Oscillator<T, CoulombStickSlip> oscillator;
      return fn(oscillator);
    }
  }
}

}  // namespace stickslip
