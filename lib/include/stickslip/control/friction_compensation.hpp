// Friction compensation: feeds forward a fraction of the observer's friction estimate. The seat
// obeys m dv_r/dt + b v_r + k x_r + F_f = -m a_u + f_a, so f_a = F_f cancels the friction; a
// fraction below 1 leaves a margin for the estimate's error (over-compensation feeds energy in).
#pragma once

#include <cmath>

#include "stickslip/control/sensor_sample.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip {

struct FrictionCompensationParams {
  double fraction = 0.8;  // of the estimate, in [0, 1]
};

template <typename T>
class FrictionCompensation {
 public:
  ConfigResult configure(const FrictionCompensationParams& p) noexcept {
    if (!(p.fraction >= 0.0 && p.fraction <= 1.0)) {
      ConfigResult r =
          refusal(std::isfinite(p.fraction) ? Status::out_of_range : Status::not_finite);
      r.message.append("fraction: must be in [0, 1], got ").append(p.fraction);
      return r;
    }
    fraction_ = ScalarTraits<T>::from_double(p.fraction);
    return {};
  }
  T step(const SensorSample<T>& s) const noexcept { return fraction_ * s.friction_estimate_n; }

 private:
  T fraction_{};
};

}  // namespace stickslip
