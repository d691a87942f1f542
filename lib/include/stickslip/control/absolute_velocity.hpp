// An absolute velocity from a measured acceleration: a leaky (band-limited) integrator,
//   dv/dt = a - v/tau,
// so that an accelerometer's offset gives a bounded velocity error (offset * tau) instead of a
// drift. Exact for an acceleration held over the sample (zero-order hold):
//   v[n] = e^{-dt/tau} v[n-1] + tau (1 - e^{-dt/tau}) a[n].
// Below 1/(2 pi tau) Hz the estimate falls off; a seat's motion (0.5-20 Hz) sits above it.
#pragma once

#include <cmath>

#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip {

struct AbsoluteVelocityParams {
  double dt_s = 1e-3;
  double time_constant_s = 2.0;  // tau of the leak
};

template <typename T>
class AbsoluteVelocity {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const AbsoluteVelocityParams& p) noexcept {
    if (!(p.dt_s > 0.0 && std::isfinite(p.dt_s))) {
      ConfigResult r = refusal(Status::out_of_range);
      r.message.append("dt_s: must be finite and > 0, got ").append(p.dt_s);
      return r;
    }
    if (!(p.time_constant_s > 0.0 && std::isfinite(p.time_constant_s))) {
      ConfigResult r = refusal(Status::out_of_range);
      r.message.append("time_constant_s: must be finite and > 0, got ").append(p.time_constant_s);
      return r;
    }
    const double decay = std::exp(-p.dt_s / p.time_constant_s);
    decay_ = S::from_double(decay);
    gain_s_ = S::from_double(p.time_constant_s * (1.0 - decay));
    reset();
    return {};
  }
  void reset(T v0 = T(0)) noexcept { v_ = v0; }
  T step(T a_m_per_s2) noexcept {
    v_ = decay_ * v_ + gain_s_ * a_m_per_s2;
    return v_;
  }
  T value() const noexcept { return v_; }

 private:
  T decay_{}, gain_s_{};
  T v_{};
};

}  // namespace stickslip
