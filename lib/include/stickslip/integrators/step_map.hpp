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

// One affine step with the generalised input g0 at its start and g1 at its end.
// Summed as (state part) + (input part): the input part does not depend on the previous step, so
// the loop-carried dependency through x and v is one multiply and two adds, not four.
template <typename T>
STICKSLIP_COMPACT_INLINE constexpr void apply_step_map(const StepMap<T>& m, T& x, T& v, T g0,
                                                       T g1) noexcept {
  const T x_next = (m.xx * x + m.xv * v) + (m.gx0 * g0 + m.gx1 * g1);
  const T v_next = (m.vx * x + m.vv * v) + (m.gv0 * g0 + m.gv1 * g1);
  x = x_next;
  v = v_next;
}

// The same map less the identity: `less_identity` holds xx - 1 and vv - 1 on its diagonal and the
// map's other coefficients as they are. Over a short block the map is near the identity: xx
// rounded to the scalar keeps only its eps, the same error every step, and an undamped seat's
// energy moves by it each time the map is applied (the reference seat: 7e-17 a step, and about
// 1e-15 on the 20 block maps of the scan that locate an end stop's contact, with one sign since
// contacts happen at one phase of the motion). xx - 1 and vv - 1 keep the full relative precision
// of the scalar, and the step adds what they give to x and v.
template <typename T>
struct NearIdentityStepMap {
  StepMap<T> less_identity;

  static NearIdentityStepMap from_double(const NearIdentityStepMap<double>& m) noexcept {
    return {StepMap<T>::from_double(m.less_identity)};
  }
};

template <typename T>
STICKSLIP_COMPACT_INLINE constexpr void apply_step_map(const NearIdentityStepMap<T>& near, T& x,
                                                       T& v, T g0, T g1) noexcept {
  const StepMap<T>& m = near.less_identity;
  const T x_next = x + ((m.xx * x + m.xv * v) + (m.gx0 * g0 + m.gx1 * g1));
  const T v_next = v + ((m.vx * x + m.vv * v) + (m.gv0 * g0 + m.gv1 * g1));
  x = x_next;
  v = v_next;
}

}  // namespace stickslip
