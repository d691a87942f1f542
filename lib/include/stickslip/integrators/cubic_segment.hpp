// The exact solution over one tick, friction held, as its Taylor polynomials to degree 3 in v_r
// and 4 in x_r: the event search of a fixed-point scalar that takes the whole step as one tick
// (ScalarTraits::kCubicEventSearch, the Q7.24 build). In scene units (dt = 1) the first terms
// left out are v_r's fourth derivative times 1/24 and x_r's fifth times 1/120, at most about
// ((k/m)^2 + (b/m)^4) dt^4 / 24 of the state's scale: 7e-10 for the reference seat at dt = 1 ms,
// below Q7.24's resolution of 6e-8. Over one step the polynomials are the exact solution to the
// format's rounding, so an event is located without bisecting the step. Multiplies, adds and
// ScalarTraits::proportion() only: no division.
#pragma once

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// Root-search iterations at most (regula falsi, Illinois variant), which bounds the work of an
// event. Near the root the values fall to a few units of the format's last place, which limits
// the root's precision more than further iterations would improve it; the accuracy this gives is
// tested at the break-away threshold (ScaledFixedPoint32Oscillator tests).
inline constexpr int kMaxCubicRootIterations = 6;

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

  // The root in (0, hi) of f = p d, given f(0) = at_lo > 0 > f(hi) = at_hi: regula falsi keeps
  // the root bracketed; the Illinois variant halves the value kept at an end that stays twice,
  // so that both ends close in.
  STICKSLIP_COMPACT_INLINE static T falling_root(Cubic<T> p, T d, T at_lo, T hi, T at_hi) noexcept {
    T lo = T(0);
    int kept = 0;  // -1: lo stayed last time, +1: hi did
    for (int iteration = 0; iteration < kMaxCubicRootIterations; ++iteration) {
      const T u = lo + (hi - lo) * S::proportion(at_lo, at_lo - at_hi);
      const T value = along(d, p(u));
      if (value == T(0) || !(u > lo && u < hi)) return u;
      if (value > T(0)) {
        lo = u;
        at_lo = value;
        if (kept > 0) at_hi = S::divide_by_power_of_two(at_hi, 1);
        kept = 1;
      } else {
        hi = u;
        at_hi = value;
        if (kept < 0) at_lo = S::divide_by_power_of_two(at_lo, 1);
        kept = -1;
      }
    }
    return lo + (hi - lo) * S::proportion(at_lo, at_lo - at_hi);
  }

  T x0_;
  T v_[5];  // v_r's coefficients and a 0: v_ + 1 is v_r / u when v_[0] = 0
};

}  // namespace stickslip
