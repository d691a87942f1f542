// The actuator between cab and seat: a force limit and a first-order lag,
//   tau df/dt + f = clamp(u, -f_max, f_max),
// exact for a command held over the sample (zero-order hold):
//   f[n] = f[n-1] + (1 - e^{-dt/tau}) (clamp(u[n]) - f[n-1]).
// The output is a convex combination of values within the limit, so it never exceeds it; tau = 0
// is an ideal actuator (f = clamp(u)). A non-finite command is replaced by 0 (fail safe: passive).
#pragma once

#include <cmath>

#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip {

struct ActuatorParams {
  double dt_s = 1e-3;
  double force_limit_n = 1000.0;  // |f| <= f_max
  double lag_time_constant_s = 0.0;
};

template <typename T>
class Actuator {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const ActuatorParams& p) noexcept {
    const auto bad = [](const char* name, const char* rule, double value) {
      ConfigResult r = refusal(std::isfinite(value) ? Status::out_of_range : Status::not_finite);
      r.message.append(name).append(": ").append(rule).append(", got ").append(value);
      return r;
    };
    if (!(p.dt_s > 0.0 && std::isfinite(p.dt_s))) return bad("dt_s", "must be > 0", p.dt_s);
    if (!(p.force_limit_n > 0.0 && std::isfinite(p.force_limit_n)))
      return bad("force_limit_n", "must be > 0", p.force_limit_n);
    if (!(p.lag_time_constant_s >= 0.0 && std::isfinite(p.lag_time_constant_s)))
      return bad("lag_time_constant_s", "must be >= 0", p.lag_time_constant_s);
    limit_n_ = S::from_double(p.force_limit_n);
    const double alpha =
        p.lag_time_constant_s == 0.0 ? 1.0 : -std::expm1(-p.dt_s / p.lag_time_constant_s);
    alpha_ = S::from_double(alpha);
    ideal_ = p.lag_time_constant_s == 0.0;
    reset();
    return {};
  }
  void reset(T force_n = T(0)) noexcept { force_n_ = force_n; }

  // The force over the next step for the command u (N).
  T step(T command_n) noexcept {
    if (!S::is_finite(command_n)) command_n = T(0);
    const T target =
        command_n > limit_n_ ? limit_n_ : (command_n < -limit_n_ ? -limit_n_ : command_n);
    // Ideal: the clamped command itself (f + (u - f) need not round back to u).
    force_n_ = ideal_ ? target : force_n_ + alpha_ * (target - force_n_);
    return force_n_;
  }
  T force_n() const noexcept { return force_n_; }
  T limit_n() const noexcept { return limit_n_; }

 private:
  T limit_n_{}, alpha_{};
  T force_n_{};
  bool ideal_ = true;
};

}  // namespace stickslip
