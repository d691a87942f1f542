// The common path of the Coulomb stick-slip step: a whole step in which nothing happens (slipping
// on without a sign change of v_r, or staying stuck). Oscillator and StickSlipBatch both call
// these functions, so that a batch lane computes exactly the operations of a single oscillator
// (bit-identical results). Branch-free, so that the batch's loop over lanes vectorises.
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "stickslip/core/scalar.hpp"
#include "stickslip/integrators/step_map.hpp"

namespace stickslip {

// x is finite, tested without any FP exception and without branches (so that a loop over lanes
// vectorises): the exponent field alone, read as a number, is +inf exactly when x is inf or NaN,
// and is never NaN itself, so comparing it is quiet whatever the compiler makes of the compare.
// (A non-IEEE scalar, fixed point, asks its traits.)
template <typename T>
inline bool finite_quietly(T x) noexcept {
  if constexpr (!std::numeric_limits<T>::is_iec559) {
    return ScalarTraits<T>::is_finite(x);
  } else {
    static_assert(std::numeric_limits<T>::is_iec559, "IEEE 754 binary formats only");
    using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
    static_assert(sizeof(Bits) == sizeof(T), "an unsigned integer of T's size");
    const T infinity = std::numeric_limits<T>::infinity();
    Bits exponent_mask, bits;
    std::memcpy(&exponent_mask, &infinity, sizeof bits);
    std::memcpy(&bits, &x, sizeof bits);
    bits &= exponent_mask;
    T exponent;
    std::memcpy(&exponent, &bits, sizeof bits);
    return exponent != infinity;
  }
}

// a_x = -(k x_r + b v_r + F_f)/m, the seat's absolute acceleration, given F_f/m.
template <typename T>
constexpr T seat_acceleration(T k_over_m, T b_over_m, T x, T v, T friction_accel) noexcept {
  return -(k_over_m * x + b_over_m * v + friction_accel);
}

template <typename T>
struct WholeSlip {
  T x, v;               // state at the end of the step
  T seat_acceleration;  // a_x at the end of the step
  T a_start, a_end;     // dv_r/dt at the start and at the end of the step
};

// A whole step slipping in direction d (+1/-1) against the constant friction F_fk d, given as
// the acceleration friction_accel = (1/m)(F_fk d), from (x, v), whose seat acceleration with that
// friction is a_x_start, with the input a0 -> a1. `map` advances one whole step (a StepMap or a
// NearIdentityStepMap).
template <typename T, typename Map>
constexpr WholeSlip<T> whole_step_slip(const Map& map, T k_over_m, T b_over_m, T friction_accel,
                                       T x, T v, T a_x_start, T a0, T a1) noexcept {
  T x_end = x, v_end = v;
  apply_step_map(map, x_end, v_end, -(a0 + friction_accel), -(a1 + friction_accel));
  const T a_x_end = seat_acceleration(k_over_m, b_over_m, x_end, v_end, friction_accel);
  return {x_end, v_end, a_x_end, a_x_start - a0, a_x_end - a1};
}

// Whether that step needs the event search: v_r d < 0 at the end, a dip (|v_r| fell and rose
// again: it may have crossed twice), or a non-finite state (a_x is non-finite iff x_r or v_r is,
// as k/m > 0). Bitwise operators only: no branches, the same code for one lane or many.
template <typename T>
inline bool slip_step_has_event(const WholeSlip<T>& s, T d) noexcept {
  const bool crossed = s.v * d < T(0);
  // Non-short-circuit on purpose (no branch); as ints, since for a class scalar (fixed point)
  // each side is a call that clang would otherwise want sequenced with &&.
  const bool dip = static_cast<int>(s.a_start * d < T(0)) & static_cast<int>(s.a_end * d > T(0));
  return crossed | dip | !finite_quietly(s.seat_acceleration);
}

// Stuck at x: the limit force F_L = -(m a_u + k x_r) at the end of the step, where the input is
// a1. It is the holding force while stuck.
template <typename T>
constexpr T stuck_limit_force(T mass_kg, T stiffness, T x, T a1) noexcept {
  return -(mass_kg * a1 + stiffness * x);
}

// |F_L| > F_fs at the end: the seat breaks away inside the step. F_L is linear in time inside
// the step, so |F_L| <= F_fs at the end means it held throughout (it held at the start).
template <typename T>
constexpr bool stuck_step_breaks_away(T limit_force_n, T static_n) noexcept {
  return !(ScalarTraits<T>::abs(limit_force_n) <= static_n);
}

}  // namespace stickslip
