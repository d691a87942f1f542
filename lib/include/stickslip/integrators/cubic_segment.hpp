// The exact solution over one tick, friction held, as its Taylor polynomials to degree 3 in v_r
// and 4 in x_r: the event search of a fixed-point scalar that takes the whole step as one tick
// (ScalarTraits::kCubicEventSearch, the Q7.24 build). In scene units (dt = 1) the first terms
// left out are v_r's fourth derivative times 1/24 and x_r's fifth times 1/120, at most about
// ((k/m)^2 + (b/m)^4) dt^4 / 24 of the state's scale: 7e-10 for the reference seat at dt = 1 ms,
// below Q7.24's resolution of 6e-8. Over one step the polynomials are the exact solution to the
// format's rounding, so an event is located without bisecting the step. Multiplies, adds,
// ScalarTraits::proportion() and one integer square root per event: no division.
#pragma once

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// Newton steps of the root search, from the root of a quadratic that takes the cubic term at
// the bracket's end: each doubles the digits, and three leave the root within a unit or two of
// the format's last place in v_r over the seats configure() accepts, where the cubic term reaches
// a third of the others ((b/m) dt up to 1); the reference seat's ((b/m) dt = 0.006) needs one
// (ScaledFixedPoint32Oscillator tests). They bound the work of an event.
inline constexpr int kCubicRootNewtonSteps = 3;

// c[0] + c[1] u + c[2] u^2 + c[3] u^3, a view of four coefficients kept elsewhere.
template <typename T>
struct Cubic {
  const T* c;
  STICKSLIP_COMPACT_INLINE T operator()(T u) const noexcept {
    return c[0] + u * (c[1] + u * (c[2] + u * c[3]));
  }
  // 2 c2 and 3 c3 as sums: the same values as the products, without a multiply each.
  STICKSLIP_COMPACT_INLINE T slope(T u) const noexcept {
    return c[1] + u * ((c[2] + c[2]) + u * (c[3] + c[3] + c[3]));
  }
};

template <typename T>
class CubicSegment {
  using S = ScalarTraits<T>;

 public:
  // From (x0, v0) with the relative acceleration a0, its rate of change (jerk) and that one's
  // (snap) at the start, in scene units, where the step is the unit of time (the Q7.24
  // configure() requires dt = 1): u is the time from the start in steps. Built in the
  // initialiser: assigned in the body, the array would first be zeroed (a memset call on the
  // Cortex-M0+).
  CubicSegment(T x0, T v0, T a0, T jerk, T snap) noexcept
      : x0_(x0), v_{v0, a0, S::divide_by_power_of_two(jerk, 1), snap * T(1.0 / 6.0), T(0)} {}

  // x_r is the integral of v_r: its coefficients are formed from v_r's where it is evaluated (at
  // a root and at the tick's end), so that the segment holds six numbers, not ten (the Cortex-M0+
  // step's stack budget).
  T position(T u) const noexcept {
    const T sum =
        v_[0] + u * (S::divide_by_power_of_two(v_[1], 1) +
                     u * (v_[2] * T(1.0 / 3.0) + u * S::divide_by_power_of_two(v_[3], 2)));
    return x0_ + u * sum;
  }
  T velocity(T u) const noexcept { return Cubic<T>{v_}(u); }

  // The first u in (0, hi] at which v_r d turns negative, given v_r d >= 0 at 0. False if v_r d
  // stays >= 0 on the interval. From rest (v_r = 0 at u = 0, a slip starting there) the search
  // runs on v_r / u, whose value at 0 is the initial acceleration: near u = 0, v_r itself is
  // below the format's resolution and would fake a crossing there.
  STICKSLIP_COMPACT_INLINE bool first_crossing(T d, T hi, T& root) const noexcept {
    return first_crossing(Cubic<T>{v_[0] == T(0) ? v_ + 1 : v_}, d, hi, root);
  }

 private:
  // The first u in (0, hi] at which p d turns negative, given p(0) d >= 0: a sign change at hi,
  // or a dip (p d falls below zero inside and rises again). p is a cubic with a tiny cubic term
  // (of relative size (b/m) dt), so it has at most one minimum in a tick. The minimum is taken
  // where the slope's linear part vanishes, u = -c1 / (2 c2): p is flat there, so the cubic term's
  // shift of that place changes the value found at it to second order only.
  STICKSLIP_COMPACT_INLINE static bool first_crossing(Cubic<T> p, T d, T hi, T& root) noexcept {
    const T at_start = along(d, p.c[0]);
    T end = hi;
    T at_end = along(d, p(hi));
    if (!(at_end < T(0))) {
      const T falling = -along(d, p.c[1]);
      const T turning = along(d, p.c[2]);
      if (!(falling > T(0) && turning > T(0) && along(d, p.slope(hi)) > T(0))) return false;
      end = S::proportion(falling, turning + turning);
      end = end < hi ? end : hi;
      at_end = along(d, p(end));
      if (!(at_end < T(0))) return false;
    }
    root = at_start > T(0) ? falling_root(p, d, at_start, end, at_end) : T(0);
    return true;
  }

  static T along(T d, T value) noexcept { return d < T(0) ? -value : value; }

  // The root in (0, hi) of f = p d, given f(0) = at_lo > 0 > f(hi) = at_hi. It starts at the
  // root of c0 + c1 u + (c2 + c3 hi) u^2, f with its cubic term taken at the bracket's end, from
  // the exact discriminant (ScalarTraits::falling_quadratic_root()), or the secant where that has
  // none in the bracket, and takes up to kCubicRootNewtonSteps Newton steps on f. It stops where
  // |f| is at most one unit of the last place: f's evaluation (three rounded products, |u| <= 1)
  // is itself uncertain by up to 1.5 units there, so a Newton step could only move u within the
  // band where f is zero to rounding (in scene units the slope is small, and such a step moves u
  // by thousands of units). The bracket closes on each value found, and a step that would leave it
  // is replaced by the bracket's midpoint (no proportion: the bound on the step's work charges
  // every branch): the search never leaves (lo, hi).
  STICKSLIP_COMPACT_INLINE static T falling_root(Cubic<T> p, T d, T at_lo, T hi, T at_hi) noexcept {
    T lo = T(0);
    T u = S::falling_quadratic_root(along(d, p.c[2] + p.c[3] * hi), along(d, p.c[1]), at_lo);
    if (!(u > lo && u < hi)) u = hi * S::proportion(at_lo, at_lo - at_hi);
    for (int step = 0; step < kCubicRootNewtonSteps; ++step) {
      const T value = along(d, p(u));
      if (S::abs(value) <= S::epsilon()) return u;
      if (value > T(0)) {
        lo = u;
      } else {
        hi = u;
      }
      const T falling = -along(d, p.slope(u));  // -f'(u)
      const T size = value > T(0) ? value : -value;
      T next = lo;
      if (falling > T(0) && size <= falling) {
        const T change = S::proportion(size, falling);
        next = value > T(0) ? u + change : u - change;
      }
      if (!(next > lo && next < hi)) next = lo + S::divide_by_power_of_two(hi - lo, 1);
      if (next == u) return u;
      u = next;
    }
    return u;
  }

  T x0_;
  T v_[5];  // v_r's coefficients and a 0: v_ + 1 is v_r / u when v_[0] = 0
};

}  // namespace stickslip
