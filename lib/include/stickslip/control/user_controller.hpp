// The user's own controller in the loop: any function of the sensor sample that returns the
// force command (N), with a context pointer for its state. One line to plug in:
//   UserController<double> c{[](const SensorSample<double>& s, void*) { return -900.0 *
//   s.v_r_m_per_s; }};
// A captureless lambda converts to the function pointer; no heap, no std::function.
#pragma once

#include "stickslip/control/sensor_sample.hpp"

namespace stickslip {

template <typename T>
struct UserController {
  using Function = T (*)(const SensorSample<T>& sample, void* context);
  Function function = nullptr;
  void* context = nullptr;
  // No function: no force (passive).
  T step(const SensorSample<T>& s) const noexcept {
    return function != nullptr ? function(s, context) : T(0);
  }
};

}  // namespace stickslip
