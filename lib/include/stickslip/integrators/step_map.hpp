// One fixed step of the linear part as an affine map, the form every integrator takes once the
// friction force is constant over the step (Coulomb slip, held friction, no friction).
#pragma once

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// Resolution of in-step events: a step is split into 2^kEventLevels ticks by bisection; inside the
// last tick the event instant is interpolated linearly (error ~ tick^2 * jerk, far below 1e-12 s).
inline constexpr int kEventLevels = 16;
inline constexpr int kMapLevels = kEventLevels + 1;  // level l advances dt / 2^l
inline constexpr unsigned kTicksPerStep = 1u << kEventLevels;

// With the generalised input g(t) = -(a_u(t) + F_f/m), linear between g0 at the start and g1 at
// the end of the step (first-order hold), every integrator of the linear part is
//   x' = xx*x + xv*v + gx0*g0 + gx1*g1
//   v' = vx*x + vv*v + gv0*g0 + gv1*g1
template <typename T>
struct StepMap {
  T xx, xv, vx, vv;
  T gx0, gx1, gv0, gv1;

  static StepMap from_double(const StepMap<double>& m) noexcept {
    using S = ScalarTraits<T>;
    return {S::from_double(m.xx),  S::from_double(m.xv),  S::from_double(m.vx),
            S::from_double(m.vv),  S::from_double(m.gx0), S::from_double(m.gx1),
            S::from_double(m.gv0), S::from_double(m.gv1)};
  }
};

}  // namespace stickslip
