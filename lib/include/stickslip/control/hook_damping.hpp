// Skyhook and groundhook: the reference controllers of seat and vehicle suspensions.
//   skyhook:    a damper to a fixed "sky", f = -c v_seat          (force on the seat)
//   groundhook: a damper from the cab to the ground, -c v_floor on the cab, so f = +c v_floor on
//               the seat (the actuator pushes the seat and the cab apart with equal forces)
// Active: the force itself (the actuator's limit and lag apply after, actuator.hpp). Semi-active:
// a controllable damper between cab and seat can only give f = -c v_r with c in [b_min, b_max];
// the desired force is clipped into that interval when it dissipates (f v_r <= 0) and the damper
// sits at b_min otherwise ("clipped" semi-active law). Then f v_r = -c v_r^2 <= 0 always: the
// device never puts energy into the seat. Division-free (no c = f/v_r).
#pragma once

#include <cmath>

#include "stickslip/control/sensor_sample.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"

namespace stickslip {

enum class HookReference : unsigned char { sky, ground };
enum class HookDevice : unsigned char { active, semi_active };

struct HookParams {
  HookReference reference = HookReference::sky;
  HookDevice device = HookDevice::semi_active;
  double gain_ns_per_m = 1500.0;         // c
  double min_damping_ns_per_m = 0.0;     // semi-active: b_min
  double max_damping_ns_per_m = 3000.0;  // semi-active: b_max
};

template <typename T>
class HookController {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const HookParams& p) noexcept {
    const auto bad = [](const char* name, const char* rule, double value) {
      ConfigResult r = refusal(std::isfinite(value) ? Status::out_of_range : Status::not_finite);
      r.message.append(name).append(": ").append(rule).append(", got ").append(value);
      return r;
    };
    if (!(p.gain_ns_per_m >= 0.0 && std::isfinite(p.gain_ns_per_m)))
      return bad("gain_ns_per_m", "must be >= 0", p.gain_ns_per_m);
    if (!(p.min_damping_ns_per_m >= 0.0 && std::isfinite(p.min_damping_ns_per_m)))
      return bad("min_damping_ns_per_m", "must be >= 0", p.min_damping_ns_per_m);
    if (!(p.max_damping_ns_per_m >= p.min_damping_ns_per_m &&
          std::isfinite(p.max_damping_ns_per_m)))
      return bad("max_damping_ns_per_m", "must be >= min_damping_ns_per_m", p.max_damping_ns_per_m);
    reference_ = p.reference;
    device_ = p.device;
    gain_ = S::from_double(p.gain_ns_per_m);
    b_min_ = S::from_double(p.min_damping_ns_per_m);
    b_max_ = S::from_double(p.max_damping_ns_per_m);
    return {};
  }

  // The force on the seat (N, upward positive) for this sample.
  T step(const SensorSample<T>& s) const noexcept {
    const T desired =
        reference_ == HookReference::sky ? -(gain_ * s.v_seat_m_per_s) : gain_ * s.v_floor_m_per_s;
    if (device_ == HookDevice::active) return desired;
    const T v = s.v_r_m_per_s;
    const T soft = -(b_min_ * v), hard = -(b_max_ * v);
    if (!(desired * v <= T(0))) return soft;  // would feed energy in: least damping
    // Between -b_min v and -b_max v (ordered by the sign of v).
    const T lo = v > T(0) ? hard : soft, hi = v > T(0) ? soft : hard;
    return desired < lo ? lo : (desired > hi ? hi : desired);
  }

 private:
  HookReference reference_ = HookReference::sky;
  HookDevice device_ = HookDevice::semi_active;
  T gain_{}, b_min_{}, b_max_{};
};

}  // namespace stickslip
