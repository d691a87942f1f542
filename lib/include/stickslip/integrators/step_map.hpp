// One fixed step of the linear part as an affine map, the form every integrator takes once the
// friction force is constant over the step (Coulomb slip, held friction, no friction).
#pragma once

#include <type_traits>

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

// The same map with the identity split off its diagonal where that keeps more of it:
//   x' = identity_x x + (rest.xx x + rest.xv v + ...), v' likewise,
// identity_x 1 and rest.xx = xx - 1 where xx > 1/2, else identity_x 0 and rest.xx = xx (the
// same for v). Over a short step the map is near the identity (xx = 1 - (omega0 h)^2/2 + ...):
// xx rounded to the scalar keeps only its eps, which against (omega0 h)^2 is a relative error of
// the frequency (the trace) and of the area (the determinant), the same every step, and an
// undamped seat's phase and energy drift with it without bound: an undamped frictionless seat's
// a_x history ended up to 8.3e-13 from the exact solution after 20 s, above the 1e-13 that an
// input change of 1e-13 moves it by, and the 20 block maps of the scan that locate each end-stop
// contact moved the energy by 1e-15, with one sign since contacts happen at one phase. xx - 1
// keeps the full relative precision of the scalar. Where xx <= 1/2 (omega0 h beyond about pi/3:
// stiff end stops) xx itself is the smaller and keeps more: there the map is the plain one.
// identity_x x is exact (x or 0).
template <typename T>
struct NearIdentityStepMap {
  StepMap<T> rest;
  T identity_x, identity_v;  // 1 or 0

  static NearIdentityStepMap from_double(const NearIdentityStepMap<double>& m) noexcept {
    using S = ScalarTraits<T>;
    return {StepMap<T>::from_double(m.rest), S::from_double(m.identity_x),
            S::from_double(m.identity_v)};
  }
};

// Double keeps its maps near the identity. Float's own rounding (6e-8) is far above that error,
// and on the Cortex-M4F the additions cost the end-stop seat 10 % of its instructions per frame;
// fixed point rounds to an absolute unit, so xx - 1 would keep no more than xx.
template <typename T>
using StepMapOf = std::conditional_t<std::is_same_v<T, double>, NearIdentityStepMap<T>, StepMap<T>>;

// A map's coefficients as it stores them (a NearIdentityStepMap's without the identity split off).
template <typename T>
constexpr const StepMap<T>& coefficients(const StepMap<T>& m) noexcept {
  return m;
}
template <typename T>
constexpr const StepMap<T>& coefficients(const NearIdentityStepMap<T>& m) noexcept {
  return m.rest;
}

// The identity's share added last, to what the map moves: the loop-carried dependency is one
// multiply and three adds, one add more than the plain map's (the whole double step 10 to 19 %
// slower, stickslip_bench_step). Adding the identity's share to the input part first keeps the
// plain map's dependency but rounds x + g every step, a rounding that follows the orbit: with it
// the energy grid of docs/DESIGN.md drifted 25 times as much (median 3.2e-11 against 1.3e-12, worst
// 7.2e-10). Where nothing is split off (identity 0) the sum is the plain map's, bit for bit.
template <typename T>
STICKSLIP_COMPACT_INLINE constexpr void apply_step_map(const NearIdentityStepMap<T>& near, T& x,
                                                       T& v, T g0, T g1) noexcept {
  const StepMap<T>& m = near.rest;
  const T x_next = near.identity_x * x + ((m.xx * x + m.xv * v) + (m.gx0 * g0 + m.gx1 * g1));
  const T v_next = near.identity_v * v + ((m.vx * x + m.vv * v) + (m.gv0 * g0 + m.gv1 * g1));
  x = x_next;
  v = v_next;
}

}  // namespace stickslip
