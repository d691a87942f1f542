// The soak's scene: the lorry-like ride (K = 0.8, b = 504 N s/m, F_fs = F_fk) and its input, the
// 600 s lorry recording at 1 ms (seed 1, RMS 0.35 m/s^2), played in a loop.
#pragma once

#include <vector>

#include "stickslip/models/oscillator.hpp"

namespace stickslip::soak {

template <typename T>
struct Scene {
  std::vector<T> input;  // one loop of the recording
  OscillatorParams params;
};

template <typename T>
Scene<T> lorry_scene();

}  // namespace stickslip::soak
