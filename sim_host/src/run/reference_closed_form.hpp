// The closed forms of the reference solver (reference_solver.hpp): the free and ramp-driven
// response of the linear oscillator over any part of a sample interval, in long double, and the
// search for the instant an event (v_r = 0) happens inside a piece of motion. Private to the run
// library; the event driver (reference_solver.cpp) and the per-law segment solvers use it.
#pragma once

#include <algorithm>
#include <cmath>

namespace stickslip::host::reference {

// The closed form and the state between samples are kept in long double (x87 extended precision
// on x86-64): the one-sample coefficients are applied up to millions of times, and a lightly
// damped or heavily over-damped seat amplifies their rounding in its steady state (the slow mode
// of a 40x critically damped seat by ~1e4); 11 more bits keep the results at double precision.
using Real = long double;

constexpr Real kPi = 3.141592653589793238462643383279502884L;
// A sample interval with more events than this is a degenerate scene (events piling up at one
// instant through rounding); the reference refuses it rather than return a doubtful answer.
constexpr int kMaxEventsPerSample = 1000;

constexpr Real wide(double value) {
  return static_cast<Real>(value);
}

// Guards against floating-point exceptions are written as if-statements, not ?: - a compiler may
// evaluate both arms of a conditional expression and select, raising the very flag guarded against.

// To double for the trace; magnitudes below 1e-300 become 0 (no underflow on narrowing).
inline double narrow(Real value) {
  if (std::fabs(value) < 1e-300L) return 0.0;
  return static_cast<double>(value);
}

// exp of an argument <= 0 without ever producing a subnormal.
inline Real decay(Real exponent) {
  if (exponent < -11000.0L) return 0.0L;
  return std::exp(exponent);
}

inline Real sign_of(Real value) {
  return value > 0 ? 1.0L : (value < 0 ? -1.0L : 0.0L);
}

// ---------------------------------------------------------------------------------------------
// Response of x'' + 2 sigma x' + omega0^2 x = g0 + q tau after a time tau, as the four functions
//   x(tau) = P x(0) + F x'(0) + G g0 + R q
//   x'(tau) = -omega0^2 F x(0) + V x'(0) + F g0 + G q
// (G' = F, R' = G, P' = -omega0^2 F, F' = V). Every term is of the size of the motion it
// describes, so nothing large cancels: writing x as a particular ramp solution plus a free motion
// instead would carry the offset 2 sigma q/omega0^4, which for a heavily damped seat under a fast
// input is 1e6 times the motion itself.
struct FreeResponse {
  Real position_from_position;  // P = e^{-sigma tau} (C + sigma S)
  Real position_from_velocity;  // F = e^{-sigma tau} S
  Real velocity_from_velocity;  // V = e^{-sigma tau} (C - sigma S)
  Real position_from_step;      // G = (1 - P)/omega0^2, response to a constant g
  Real position_from_ramp;      // R = (tau - F - 2 sigma G)/omega0^2, response to g = tau
};

// C = cos(w tau), S = sin(w tau)/w with w^2 = omega0^2 - sigma^2 of either sign (cosh and sinh/mu
// when over-damped, 1 and tau when critically damped): continuous through critical damping, no
// division by a small w. Strongly over-damped pieces use the two real exponentials with the slow
// rate computed as -omega0^2/(sigma + mu), free of cancellation.
class FreeModes {
 public:
  FreeModes(Real mass, Real stiffness, Real damping) {
    sigma_ = damping / (2 * mass);
    omega0_sq_ = stiffness / mass;
    const Real discriminant = (4 * stiffness * mass - damping * damping) / (4 * mass * mass);
    if (discriminant > 0) {
      kind_ = Kind::under;
      rate_ = std::sqrt(discriminant);  // omega_d
    } else if (discriminant < 0) {
      kind_ = Kind::over;
      rate_ = std::sqrt(-discriminant);  // mu
      slow_ = -omega0_sq_ / (sigma_ + rate_);
      fast_ = -(sigma_ + rate_);
    } else {
      kind_ = Kind::critical;
      rate_ = 0;
    }
  }

  Real sigma() const { return sigma_; }
  Real omega0_sq() const { return omega0_sq_; }

  // Longest piece of time in which the acceleration of a free motion (a damped sinusoid with zeros
  // pi/omega_d apart) has at most one zero, with a margin of two; unbounded when not oscillating.
  Real max_piece_s() const {
    if (kind_ != Kind::under) return -1;
    return kPi / (2 * rate_);
  }

  FreeResponse at(Real tau) const {
    FreeResponse r = free_motion(tau);
    if (tau <= 0) return r;
    // G and R are small where tau is short against the seat's time scales, and the closed forms
    // (1 - P)/omega0^2 ... would then lose digits in the subtraction - too many for a heavily
    // damped seat, whose slow mode (P ~ 1 - omega0^2 tau/(2 sigma)) also amplifies coefficient
    // errors in the steady state. Hence: Taylor series for short pieces, the two real exponentials
    // through expm1 for well-separated over-damped modes, the closed form otherwise (where P is
    // well below 1).
    const Real fast_rate = 2 * sigma_ > std::sqrt(omega0_sq_) ? 2 * sigma_ : std::sqrt(omega0_sq_);
    if (fast_rate * tau <= 1.5L) {
      series(tau, r.position_from_step, r.position_from_ramp);
    } else if (kind_ == Kind::over && 2 * rate_ * tau >= 1) {
      const Real zs = slow_ * tau, zf = fast_ * tau;
      r.position_from_step = tau * (phi1(zs) - phi1(zf)) / (zs - zf) * tau;
      r.position_from_ramp = tau * tau * (phi2(zs) - phi2(zf)) / (zs - zf) * tau;
    } else {
      // 1 - P = (1 - e) + e (1 - C) - e sigma S with 1 - C = 2 sin^2(w tau/2) (or -2 sinh^2).
      const Real e = decay(-sigma_ * tau);
      Real one_minus_c = 0, s = tau;
      if (kind_ == Kind::under) {
        const Real half = std::sin(rate_ * tau / 2);
        one_minus_c = 2 * half * half;
        s = std::sin(rate_ * tau) / rate_;
      } else if (kind_ == Kind::over) {
        const Real half = std::sinh(rate_ * tau / 2);
        one_minus_c = -2 * half * half;
        s = std::sinh(rate_ * tau) / rate_;
      }
      const Real one_minus_p = -std::expm1(-sigma_ * tau) + e * one_minus_c - e * sigma_ * s;
      r.position_from_step = one_minus_p / omega0_sq_;
      r.position_from_ramp =
          (tau - r.position_from_velocity - 2 * sigma_ * r.position_from_step) / omega0_sq_;
    }
    return r;
  }

 private:
  // P, F and V (the free motion).
  FreeResponse free_motion(Real tau) const {
    if (kind_ == Kind::under) {
      const Real e = decay(-sigma_ * tau);
      const Real c = std::cos(rate_ * tau);
      const Real s = std::sin(rate_ * tau) / rate_;
      return {e * (c + sigma_ * s), e * s, e * (c - sigma_ * s), 0, 0};
    }
    if (kind_ == Kind::critical) {
      const Real e = decay(-sigma_ * tau);
      return {e * (1 + sigma_ * tau), e * tau, e * (1 - sigma_ * tau), 0, 0};
    }
    if (rate_ * tau <= 0.5L) {
      const Real e = decay(-sigma_ * tau);
      const Real c = std::cosh(rate_ * tau);
      const Real s = std::sinh(rate_ * tau) / rate_;
      return {e * (c + sigma_ * s), e * s, e * (c - sigma_ * s), 0, 0};
    }
    const Real e_slow = decay(slow_ * tau), e_fast = decay(fast_ * tau);
    const Real inv = 1 / (2 * rate_);
    return {(-fast_ * e_slow + slow_ * e_fast) * inv, (e_slow - e_fast) * inv,
            (slow_ * e_slow - fast_ * e_fast) * inv, 0, 0};
  }

  // G and R by their Taylor series: y'' = g - 2 sigma y' - omega0^2 y from rest, with g = 1 for G
  // and R = integral of G. c holds the terms a_n tau^n.
  void series(Real tau, Real& step, Real& ramp) const {
    Real c0 = 0, c1 = 0;  // terms n and n + 1
    step = 0;
    ramp = 0;
    for (int n = 0; n < 100; ++n) {
      const Real c2 = (n == 0 ? tau * tau / 2 : Real(0)) - 2 * sigma_ * tau / (n + 2) * c1 -
                      omega0_sq_ * tau * tau / ((n + 2) * (n + 1)) * c0;  // term n + 2
      step += c2;
      ramp += c2 * tau / (n + 3);
      if (n > 0 && std::fabs(c2) + std::fabs(c1) <= 1e-22L * std::fabs(step)) break;
      c0 = c1;
      c1 = c2;
    }
  }
  // phi1(z) = (e^z - 1)/z and phi2(z) = (e^z - 1 - z)/z^2 for z <= 0, without cancellation.
  static Real phi1(Real z) {
    if (z == 0) return 1;
    return std::expm1(z) / z;
  }
  static Real phi2(Real z) {
    if (z > -1) {  // series: 1/2 + z/6 + z^2/24 + ...
      Real term = 0.5L, sum = 0.5L;
      for (int n = 3; n < 40 && std::fabs(term) > 1e-22L * sum; ++n) {
        term *= z / n;
        sum += term;
      }
      return sum;
    }
    return (std::expm1(z) - z) / (z * z);
  }

  enum class Kind { under, critical, over };
  Kind kind_ = Kind::under;
  Real sigma_ = 0, omega0_sq_ = 0, rate_ = 0, slow_ = 0, fast_ = 0;
};

// Position, velocity, acceleration (dv_r/dt) and jerk of the relative motion at one instant.
struct Kinematics {
  Real x, v, a, jerk;
};

// The motion while the friction force is constant and the input a ramp: x'' + 2 sigma x' +
// omega0^2 x = g0 + q tau with g0 = -(a_u(start) + F_f/m), q = -da_u/dt.
class RampMotion {
 public:
  RampMotion(const FreeModes& modes, Real x0, Real v0, Real a_u_start, Real a_u_slope,
             Real force_over_mass)
      : modes_(&modes), x0_(x0), v0_(v0), g0_(-(a_u_start + force_over_mass)), q_(-a_u_slope) {}

  Kinematics at(const FreeResponse& r, Real tau) const {
    const Real w2 = modes_->omega0_sq(), two_sigma = 2 * modes_->sigma();
    const Real x = r.position_from_position * x0_ + r.position_from_velocity * v0_ +
                   r.position_from_step * g0_ + r.position_from_ramp * q_;
    const Real v = -w2 * r.position_from_velocity * x0_ + r.velocity_from_velocity * v0_ +
                   r.position_from_velocity * g0_ + r.position_from_step * q_;
    const Real a = g0_ + q_ * tau - two_sigma * v - w2 * x;
    const Real jerk = q_ - two_sigma * a - w2 * v;
    return {x, v, a, jerk};
  }
  Kinematics operator()(Real tau) const { return at(modes_->at(tau), tau); }
  // At the start, exactly.
  Kinematics start() const {
    const Real w2 = modes_->omega0_sq(), two_sigma = 2 * modes_->sigma();
    const Real a = g0_ - two_sigma * v0_ - w2 * x0_;
    return {x0_, v0_, a, q_ - two_sigma * a - w2 * v0_};
  }

 private:
  const FreeModes* modes_;
  Real x0_, v0_, g0_, q_;
};

// ---------------------------------------------------------------------------------------------
// Root of f on [lo, hi] where f > 0 just after lo (taken as given, not evaluated) and f(hi) <= 0:
// Newton with the analytic derivative, kept inside the shrinking bracket and replaced by bisection
// whenever it leaves the bracket or stops halving |f| (rtsafe). `value_and_slope(t)` returns
// {f(t), f'(t)}. Returns a point within `tolerance` of the root, on the non-positive side when the
// bracket closes.
template <typename ValueAndSlope>
inline Real solve_descending(const ValueAndSlope& value_and_slope, Real lo, Real hi,
                             Real tolerance) {
  Real t = lo + (hi - lo) / 2;
  Real step = hi - lo, previous_step = step;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const auto [f, slope] = value_and_slope(t);
    if (f > 0) {
      lo = t;
    } else if (f < 0) {
      hi = t;
    } else {
      return t;
    }
    if (hi - lo <= tolerance) return hi;
    // Newton's step -f/slope, tested without dividing: it must land strictly inside (lo, hi)
    // and be less than half the step before last.
    const Real reach = hi - lo;
    const bool newton = slope != 0 && std::fabs(f) < std::fabs(slope) * reach &&
                        2 * std::fabs(f) < std::fabs(slope * previous_step);
    Real next = lo + (hi - lo) / 2;
    if (newton) {
      const Real candidate = t - f / slope;
      if (candidate > lo && candidate < hi) next = candidate;
    }
    previous_step = step;
    step = std::fabs(next - t);
    t = next;
    if (step <= tolerance) return t;
  }
  return hi;
}

struct Crossing {
  bool found = false;
  Real tau = 0;
  bool degenerate = false;  // the seat could not leave its rest point at all: it sticks
};

// First instant in (ta, tb] at which the velocity in the slip direction d, w = d v, reaches 0.
// `motion(t)` gives the kinematics on the piece; ka and kb are those at its ends. The piece holds
// at most one zero of the acceleration, so w has at most one extremum in it:
//   - w rising at ta: a crossing needs w(tb) <= 0, and then lies after the maximum (located from
//     the sign change of a);
//   - w falling at ta: either it keeps falling (crossing iff w(tb) <= 0), or it has a minimum
//     inside (a from - to +): the crossing, if w dips to 0 there, lies before the minimum. This is
//     the double root the end values alone would miss.
// A slip phase starting at rest (v = 0 at ta, after break-away or reversal) departs in d: the stick
// logic guarantees d a >= 0 there (and d jerk > 0 if d a = 0), so w counts as rising whatever the
// rounding in a.
template <typename Motion>
Crossing find_crossing(const Motion& motion, Real d, Real ta, const Kinematics& ka, Real tb,
                       const Kinematics& kb, Real tolerance) {
  const Real wa = d * ka.v, wb = d * kb.v;
  const bool departing = ka.v == 0;
  const Real sa = departing ? Real(1) : d * ka.a;
  const Real sb = d * kb.a;
  const auto velocity = [&](Real t) {
    const Kinematics k = motion(t);
    return std::array<Real, 2>{d * k.v, d * k.a};
  };
  const auto acceleration = [&](Real t) {
    const Kinematics k = motion(t);
    return std::array<Real, 2>{d * k.a, d * k.jerk};
  };
  const auto deceleration = [&](Real t) {
    const Kinematics k = motion(t);
    return std::array<Real, 2>{-d * k.a, -d * k.jerk};
  };
  if (sa >= 0) {
    if (sb >= 0 || wb > 0) return {};  // w never falls, or is still positive at the end
    const Real t_max = solve_descending(acceleration, ta, tb, tolerance);
    const Real w_max = d * motion(t_max).v;
    if (w_max > 0) return {true, solve_descending(velocity, t_max, tb, tolerance), false};
    if (wa > 0) return {true, solve_descending(velocity, ta, t_max, tolerance), false};
    return {true, t_max, true};  // departed by less than the rounding of v: it cannot leave
  }
  if (sb <= 0) {  // falling throughout
    if (wb > 0) return {};
    return {true, solve_descending(velocity, ta, tb, tolerance), false};
  }
  const Real t_min = solve_descending(deceleration, ta, tb, tolerance);
  if (d * motion(t_min).v > 0) return {};  // the dip stays above 0
  return {true, solve_descending(velocity, ta, t_min, tolerance), false};
}

}  // namespace stickslip::host::reference
