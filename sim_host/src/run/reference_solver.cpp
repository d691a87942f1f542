// The event-driven reference solver (see reference_solver.hpp for the method).
#include "stickslip/host/run/reference_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include <fmt/format.h>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>

#include "stickslip/host/error.hpp"
#include "stickslip/integrators/discretisation.hpp"

namespace stickslip::host {
namespace {

namespace odeint = boost::numeric::odeint;

// The closed form and the state between samples are kept in long double (x87 extended precision
// on x86-64): the one-sample coefficients are applied up to millions of times, and a lightly
// damped or heavily over-damped seat amplifies their rounding in its steady state (the slow mode
// of a 40x critically damped seat by ~1e4); 11 more bits keep the results at double precision.
using Real = long double;

constexpr Real kPi = 3.141592653589793238462643383279502884L;
// A sample interval with more events than this is a degenerate scene (events piling up at one
// instant through rounding); the reference refuses it rather than return a doubtful answer.
constexpr int kMaxEventsPerSample = 1000;
// Step tolerances of the adaptive integration (Stribeck, smooth laws).
constexpr double kOdeRelativeTolerance = 1e-15;
constexpr double kOdeAbsoluteTolerance = 1e-18;  // m and m/s
constexpr int kMaxRejectedSteps = 200;
// Near v_r = 0 (|v_r| below kVelocityBand velocity scales of the law) a step may change v_r by at
// most kVelocityResolution scales.
constexpr double kVelocityBand = 20.0;
constexpr double kVelocityResolution = 0.1;

constexpr Real wide(double value) {
  return static_cast<Real>(value);
}

// Guards against floating-point exceptions are written as if-statements, not ?: - a compiler may
// evaluate both arms of a conditional expression and select, raising the very flag guarded against.

// To double for the trace; magnitudes below 1e-300 become 0 (no underflow on narrowing).
double narrow(Real value) {
  if (std::fabs(value) < 1e-300L) return 0.0;
  return static_cast<double>(value);
}

// exp of an argument <= 0 without ever producing a subnormal.
Real decay(Real exponent) {
  if (exponent < -11000.0L) return 0.0L;
  return std::exp(exponent);
}

Real sign_of(Real value) {
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
Real solve_descending(const ValueAndSlope& value_and_slope, Real lo, Real hi, Real tolerance) {
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

// ---------------------------------------------------------------------------------------------
using OdeState = std::array<double, 2>;  // x_r, v_r
using CashKarp54 = odeint::runge_kutta_cash_karp54<OdeState>;
using ControlledCashKarp54 = odeint::controlled_runge_kutta<CashKarp54>;

enum class Law { linear, coulomb, stribeck, smooth };

// Boost's steppers keep std::array temporaries that their default constructor leaves
// uninitialised; copying one into the controlled stepper makes GCC warn (a false positive: they
// are written before being read).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
class Solver {
 public:
  Solver(const OscillatorParams& p, const std::vector<double>& a_u)
      : p_(p),
        a_u_(a_u),
        mass_(wide(p.mass_kg)),
        stiffness_(wide(p.stiffness_n_per_m)),
        damping_(wide(p.damping_ns_per_m)),
        dt_(wide(p.dt_s)),
        modes_(mass_, stiffness_, damping_),
        full_sample_(modes_.at(dt_)),
        controlled_(
            odeint::make_controlled(kOdeAbsoluteTolerance, kOdeRelativeTolerance, CashKarp54())) {
    switch (p.model) {
      case FrictionModel::linear:
        law_ = Law::linear;
        break;
      case FrictionModel::signum:
      case FrictionModel::stick_slip:
        law_ = Law::coulomb;
        break;
      case FrictionModel::stribeck:
        law_ = Law::stribeck;
        break;
      case FrictionModel::smooth:
        law_ = Law::smooth;
        break;
    }
    kinetic_ = law_ == Law::linear ? 0.0L : wide(p.kinetic_friction_n);
    // signum's Filippov solution is stick-slip with F_fs = F_fk.
    static_ = p.model == FrictionModel::signum ? kinetic_ : wide(p.static_friction_n);
    piece_ = modes_.max_piece_s();
    closed_form_tolerance_ = 4e-19L * dt_;
    ode_tolerance_ = 1e-15L * dt_;
    // A step of the adaptive integrator stays well inside a quarter period, as the event search
    // needs (at most one extremum of v_r per step).
    max_ode_step_ = p.dt_s;
    const double quarter_period = 0.5 / std::sqrt(p.stiffness_n_per_m / p.mass_kg);
    if (quarter_period < max_ode_step_) max_ode_step_ = quarter_period;
    ode_step_ = max_ode_step_ * 1e-2;
    if (p.model == FrictionModel::stribeck)
      inv_stribeck_velocity_ = 1.0 / p.stribeck_velocity_m_per_s;
    if (p.model == FrictionModel::stribeck && p.static_friction_n > p.kinetic_friction_n) {
      velocity_scale_ = p.stribeck_velocity_m_per_s;
    } else if (p.model == FrictionModel::smooth && p.kinetic_friction_n > 0.0) {
      velocity_scale_ = 1.0 / p.smoothing_constant_s_per_m;
    }
  }

  ReferenceTrace run(double x0, double v0) {
    const std::size_t count = a_u_.size();
    ReferenceTrace trace;
    trace.x_r_m.resize(count);
    trace.v_r_m_per_s.resize(count);
    trace.a_x_m_per_s2.resize(count);
    trace.friction_n.resize(count);
    trace.stuck.resize(count);

    x_ = wide(x0);
    v_ = wide(v0);
    direction_ = 0;
    if (law_ == Law::coulomb || law_ == Law::stribeck) {
      const Real limit = limit_force(wide(a_u_[0]));
      if (v_ != 0) {
        direction_ = sign_of(v_);
      } else if (std::fabs(limit) > static_) {
        direction_ = sign_of(limit);
      }
    } else {
      direction_ = 1;  // never stuck
    }
    record(trace, 0);
    for (std::size_t n = 1; n < count; ++n) {
      sample_ = n;
      const Real a0 = wide(a_u_[n - 1]), a1 = wide(a_u_[n]);
      switch (law_) {
        case Law::linear:
          advance_linear(a0, a1);
          break;
        case Law::coulomb:
        case Law::stribeck:
          advance_sticking(a0, a1);
          break;
        case Law::smooth:
          advance_smooth();
          break;
      }
      record(trace, n);
    }
    trace.stuck_time_s = narrow(static_cast<Real>(whole_samples_stuck_) * dt_ + partial_stuck_s_);
    trace.events = events_;
    return trace;
  }

 private:
  Real limit_force(Real a_u) const { return -(mass_ * a_u + stiffness_ * x_); }
  // a_u at tau inside the current sample (exact at both ends).
  Real input_at(Real a0, Real a1, Real tau) const {
    if (a0 == a1) return a0;  // a constant input stays bit-exact (the stick decisions rely on it)
    const Real phi = tau / dt_;
    return (1 - phi) * a0 + phi * a1;
  }

  // Friction of the law while moving with velocity v in direction d (d = sign of the slip).
  double friction(double v, double d) const {
    const double fk = p_.kinetic_friction_n;
    switch (law_) {
      case Law::linear:
        return 0.0;
      case Law::coulomb:
        return fk * d;
      case Law::stribeck:
        return d * (fk + (p_.static_friction_n - fk) * stribeck_shape(v));
      case Law::smooth:
        break;
    }
    const double cv = p_.smoothing_constant_s_per_m * v;
    switch (p_.smoothing) {
      case SmoothingLaw::atan:
        return fk * (2.0 / static_cast<double>(kPi)) * std::atan(cv);
      case SmoothingLaw::tanh:
        return fk * std::tanh(cv);
      case SmoothingLaw::erf:
        return fk * std::erf(cv);
      case SmoothingLaw::rational:
        break;
    }
    return fk * cv / (1.0 + std::fabs(cv));
  }
  // exp(-(v/v_S)^2), set to 0 beyond |v| = 20 v_S (e^-400: nothing against F_fk) and to 1 below
  // 1e-100 v_S, so that no intermediate underflows.
  double stribeck_shape(double v) const {
    const double r = std::fabs(v) * inv_stribeck_velocity_;
    if (r > 20.0) return 0.0;
    if (r < 1e-100) return 1.0;
    return std::exp(-r * r);
  }
  // dF_f/dv, for the jerk (the event search's Newton slope).
  double friction_slope(double v, double d) const {
    const double fk = p_.kinetic_friction_n;
    if (law_ == Law::stribeck) {
      const double r = std::fabs(v) * inv_stribeck_velocity_;
      if (r > 20.0 || r < 1e-100) return 0.0;
      return -d * (p_.static_friction_n - fk) * 2.0 * v * inv_stribeck_velocity_ *
             inv_stribeck_velocity_ * std::exp(-r * r);
    }
    if (law_ != Law::smooth) return 0.0;
    const double c = p_.smoothing_constant_s_per_m, cv = c * v;
    switch (p_.smoothing) {
      case SmoothingLaw::atan:
        return fk * (2.0 / static_cast<double>(kPi)) * c / (1.0 + cv * cv);
      case SmoothingLaw::tanh: {
        const double t = std::tanh(cv);
        return fk * c * (1.0 - t * t);
      }
      case SmoothingLaw::erf:
        if (std::fabs(cv) > 20.0) return 0.0;
        return fk * c * (2.0 / std::sqrt(static_cast<double>(kPi))) * std::exp(-cv * cv);
      case SmoothingLaw::rational:
        break;
    }
    const double denominator = 1.0 + std::fabs(cv);
    return fk * c / (denominator * denominator);
  }

  void record(ReferenceTrace& trace, std::size_t n) const {
    const Real a_u = wide(a_u_[n]);
    trace.x_r_m[n] = narrow(x_);
    trace.v_r_m_per_s[n] = narrow(v_);
    if (direction_ == 0) {  // stuck: the friction holds F_L and the seat moves with the floor
      trace.friction_n[n] = narrow(limit_force(a_u));
      trace.a_x_m_per_s2[n] = a_u_[n];
      trace.stuck[n] = 1;
      return;
    }
    const Real force = wide(friction(static_cast<double>(v_), static_cast<double>(direction_)));
    trace.friction_n[n] = narrow(force);
    trace.a_x_m_per_s2[n] = narrow(-(stiffness_ * x_ + damping_ * v_ + force) / mass_);
    trace.stuck[n] = 0;
  }

  void count_event(int& events_in_sample) {
    ++events_;
    if (++events_in_sample > kMaxEventsPerSample) {
      throw HostError(fmt::format(
          "reference solver: more than {} events in the sample interval ending at sample {} "
          "(t = {} s): a degenerate scene",
          kMaxEventsPerSample, sample_, static_cast<double>(sample_) * p_.dt_s));
    }
  }

  // At a v_r = 0 instant: stick if the limit force is within static friction, else reverse.
  void decide_at_rest(Real a_u, bool must_stick) {
    v_ = 0;
    const Real limit = limit_force(a_u);
    direction_ = must_stick || std::fabs(limit) <= static_ ? Real(0) : sign_of(limit);
  }

  void add_stuck(Real from, Real to) {
    if (from == 0 && to == dt_) {
      ++whole_samples_stuck_;
    } else {
      partial_stuck_s_ += to - from;
    }
  }

  // Stuck from tau: F_L is linear in time inside the sample; stays stuck to the end, or breaks
  // away where |F_L| reaches F_fs (returns the instant, with direction_ set).
  Real stuck_until(Real a0, Real a1, Real tau, int& events_in_sample) {
    const Real limit_end = limit_force(a1);
    if (std::fabs(limit_end) <= static_) {
      add_stuck(tau, dt_);
      return dt_;
    }
    const Real d = sign_of(limit_end);
    // F_L = d F_fs where a_u = -(d F_fs + k x)/m.
    Real tau_break = tau;
    if (a1 != a0) {
      const Real a_break = -(d * static_ + stiffness_ * x_) / mass_;
      tau_break = dt_ * ((a_break - a0) / (a1 - a0));
      if (!(tau_break > tau)) tau_break = tau;
      if (tau_break > dt_) tau_break = dt_;
    }
    add_stuck(tau, tau_break);
    direction_ = d;
    v_ = 0;
    count_event(events_in_sample);
    return tau_break;
  }

  void advance_linear(Real a0, Real a1) {
    const RampMotion motion(modes_, x_, v_, a0, (a1 - a0) / dt_, 0);
    const Kinematics end = motion.at(full_sample_, dt_);
    x_ = end.x;
    v_ = end.v;
  }

  // One sample interval of a sticking law: stuck phases in closed form, slip phases in closed form
  // (Coulomb) or by the adaptive integrator (Stribeck), as many events as occur.
  void advance_sticking(Real a0, Real a1) {
    const Real slope = (a1 - a0) / dt_;
    Real tau = 0;
    int events_in_sample = 0;
    while (tau < dt_) {
      if (direction_ == 0) {
        tau = stuck_until(a0, a1, tau, events_in_sample);
        continue;
      }
      Crossing crossing;
      Real tau_event = 0;
      if (law_ == Law::coulomb) {
        crossing = slip_closed_form(a0, a1, slope, tau, tau_event);
      } else {
        crossing = slip_ode(a0, a1, tau, tau_event);
      }
      if (!crossing.found) return;  // slipping to the end of the sample
      tau = tau_event;
      count_event(events_in_sample);
      decide_at_rest(input_at(a0, a1, tau), crossing.degenerate);
    }
  }

  // Coulomb slip from tau with friction F_fk d: the closed form, searched piece by piece for the
  // first v_r = 0 instant. Leaves the state at the event (tau_event) or at the sample end.
  Crossing slip_closed_form(Real a0, Real a1, Real slope, Real tau, Real& tau_event) {
    const Real d = direction_;
    const RampMotion motion(modes_, x_, v_, input_at(a0, a1, tau), slope, kinetic_ * d / mass_);
    const Real length = dt_ - tau;
    Real ta = 0;
    Kinematics ka = motion.start();
    while (ta < length) {
      Real tb = length;
      if (piece_ > 0 && tb - ta > piece_) tb = ta + piece_;
      const Kinematics kb = tau == 0 && tb == length ? motion.at(full_sample_, tb) : motion(tb);
      const Crossing crossing = find_crossing(motion, d, ta, ka, tb, kb, closed_form_tolerance_);
      if (crossing.found) {
        x_ = motion(crossing.tau).x;
        v_ = 0;
        tau_event = tau + crossing.tau;
        if (tau_event > dt_) tau_event = dt_;
        return crossing;
      }
      ta = tb;
      ka = kb;
      // Rising or departing w that rounds below 0 at a piece end is at rest, not reversed.
      if (d * ka.v < 0) ka.v = 0;
    }
    x_ = ka.x;
    v_ = ka.v;
    return {};
  }

  // --- adaptive integration (Stribeck slip, smooth laws) -------------------------------------
  struct OdeSystem {
    const Solver* solver;
    double a0, a_slope, direction;
    void operator()(const OdeState& s, OdeState& ds, double t) const {
      ds[0] = s[1];
      ds[1] = solver->relative_acceleration(s[0], s[1], direction, a0 + a_slope * t);
    }
  };
  double relative_acceleration(double x, double v, double d, double a_u) const {
    return -(p_.stiffness_n_per_m * x + p_.damping_ns_per_m * v + friction(v, d)) / p_.mass_kg -
           a_u;
  }
  Kinematics kinematics(const OdeSystem& system, const OdeState& s, double t) const {
    const double a =
        relative_acceleration(s[0], s[1], system.direction, system.a0 + system.a_slope * t);
    const double jerk = -(p_.stiffness_n_per_m * s[1] +
                          (p_.damping_ns_per_m + friction_slope(s[1], system.direction)) * a) /
                            p_.mass_kg -
                        system.a_slope;
    return {wide(s[0]), wide(s[1]), wide(a), wide(jerk)};
  }

  // One accepted adaptive step from t (capped at t_end); returns the new time.
  double ode_step(const OdeSystem& system, const OdeState& from, double t, double t_end,
                  OdeState& to) {
    for (int rejected = 0; rejected <= kMaxRejectedSteps; ++rejected) {
      double h = ode_step_ < max_ode_step_ ? ode_step_ : max_ode_step_;
      bool last = false;
      if (t + h >= t_end - 1e-12 * p_.dt_s) {
        h = t_end - t;
        last = true;
      }
      double t_new = t;
      double h_next = h;
      if (controlled_.try_step(system, from, t_new, to, h_next) == odeint::success) {
        // Where |v_r| is within a few velocity scales of the law (v_S, 1/c), its friction changes
        // over a small velocity: a step must not change v_r by more than a fraction of that scale,
        // or its stages can miss the change and its error estimate with them.
        if (velocity_scale_ > 0.0) {
          const double low = std::min(from[1], to[1]), high = std::max(from[1], to[1]);
          const double band = kVelocityBand * velocity_scale_;
          const double resolved = kVelocityResolution * velocity_scale_;
          if (low < band && high > -band && high - low > resolved) {
            ode_step_ = h * std::max(0.1, 0.9 * resolved / (high - low));
            continue;
          }
          if (low < band && high > -band && h_next > 2.0 * h) h_next = 2.0 * h;
        }
        if (!last || h_next < ode_step_) ode_step_ = h_next;  // a capped last step says little
        return last ? t_end : t_new;
      }
      ode_step_ = h_next;
    }
    throw HostError(fmt::format(
        "reference solver: the adaptive integrator cannot meet its tolerance in the sample "
        "interval ending at sample {} (step {} s)",
        sample_, ode_step_));
  }

  // Stribeck slip from tau in direction d, adaptively, with the event search inside each step.
  Crossing slip_ode(Real a0, Real a1, Real tau, Real& tau_event) {
    const double dt = p_.dt_s;
    const OdeSystem system{this, static_cast<double>(a0), static_cast<double>((a1 - a0) / dt_),
                           static_cast<double>(direction_)};
    const Real d = direction_;
    double t = static_cast<double>(tau);
    OdeState state{narrow(x_), narrow(v_)};
    Kinematics ka = kinematics(system, state, t);
    // Leaving rest, the Stribeck friction falls from F_fs to F_fk within |v_r| ~ v_S, in
    // microseconds: a step that jumps over that drop sees it at too few stages for its error
    // estimate to notice. Start small and let the controller grow the step (x4.5 per step).
    if (v_ == 0 && ode_step_ > 1e-6 * p_.dt_s) ode_step_ = 1e-6 * p_.dt_s;
    while (t < dt) {
      OdeState next{};
      const double t_next = ode_step(system, state, t, dt, next);
      const Kinematics kb = kinematics(system, next, t_next);
      // The state inside the step: one step of the partial length from its start.
      const auto motion = [&, t](Real offset) {
        if (offset <= 0) return kinematics(system, state, t);
        OdeState out{};
        controlled_.stepper().do_step(system, state, t, out, static_cast<double>(offset));
        return kinematics(system, out, t + static_cast<double>(offset));
      };
      const Crossing crossing =
          find_crossing(motion, d, 0, ka, wide(t_next - t), kb, ode_tolerance_);
      if (crossing.found) {
        x_ = motion(crossing.tau).x;
        v_ = 0;
        tau_event = wide(t) + crossing.tau;
        if (tau_event > dt_) tau_event = dt_;
        return crossing;
      }
      state = next;
      ka = kb;
      if (d * ka.v < 0) {
        state[1] = 0.0;
        ka.v = 0;
      }
      t = t_next;
    }
    x_ = wide(state[0]);
    v_ = wide(state[1]);
    return {};
  }

  // Smooth laws: no events. The rational form c v/(1 + c|v|) has a jump in its second derivative
  // at v_r = 0, which costs a Runge-Kutta step its order: steps are ended at the v_r = 0 instants
  // (found like the events of the sticking laws), so that no step integrates across the kink.
  void advance_smooth() {
    const double a0 = a_u_[sample_ - 1], a1 = a_u_[sample_];
    const OdeSystem system{this, a0, (a1 - a0) / p_.dt_s, 1.0};
    const bool kink = p_.smoothing == SmoothingLaw::rational;
    OdeState state{narrow(x_), narrow(v_)};
    double t = 0.0;
    int restarts = 0;
    while (t < p_.dt_s) {
      OdeState next{};
      const double t_next = ode_step(system, state, t, p_.dt_s, next);
      if (kink && restarts < kMaxEventsPerSample) {
        const Kinematics ka = kinematics(system, state, t), kb = kinematics(system, next, t_next);
        // The side v_r leaves 0 towards (or is on): the sign of a at rest.
        const Real d = ka.v != 0 ? sign_of(ka.v) : (ka.a < 0 ? Real(-1) : Real(1));
        const auto motion = [&, t](Real offset) {
          if (offset <= 0) return kinematics(system, state, t);
          OdeState out{};
          controlled_.stepper().do_step(system, state, t, out, static_cast<double>(offset));
          return kinematics(system, out, t + static_cast<double>(offset));
        };
        const Crossing crossing =
            find_crossing(motion, d, 0, ka, wide(t_next - t), kb, ode_tolerance_);
        // (A crossing within rounding of either end is left inside the step: no progress to make.)
        const double t_cross = t + static_cast<double>(crossing.tau);
        if (crossing.found && t_cross > t + 1e-12 * p_.dt_s && t_cross < t_next - 1e-12 * p_.dt_s) {
          const Kinematics at = motion(crossing.tau);
          state = {narrow(at.x), 0.0};
          t = t_cross;
          ++restarts;
          continue;
        }
      }
      state = next;
      t = t_next;
    }
    x_ = wide(state[0]);
    v_ = wide(state[1]);
  }

  const OscillatorParams& p_;
  const std::vector<double>& a_u_;
  Law law_ = Law::linear;
  Real mass_, stiffness_, damping_, dt_;
  Real kinetic_ = 0, static_ = 0;
  FreeModes modes_;
  FreeResponse full_sample_;  // the free response over a whole sample interval
  Real piece_ = 0;
  Real closed_form_tolerance_ = 0, ode_tolerance_ = 0;
  double inv_stribeck_velocity_ = 0.0;
  ControlledCashKarp54 controlled_;
  double max_ode_step_ = 0.0, ode_step_ = 0.0;
  double velocity_scale_ = 0.0;  // of the friction law (v_S, 1/c); 0: none

  // State.
  Real x_ = 0, v_ = 0;
  Real direction_ = 0;  // 0 stuck, +1/-1 slipping (smooth and linear: always 1)
  std::size_t sample_ = 0;
  std::uint64_t events_ = 0;
  std::uint64_t whole_samples_stuck_ = 0;  // stuck time: whole samples counted exactly...
  Real partial_stuck_s_ = 0;               // ...plus the located parts
};
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace

ReferenceTrace solve_reference(const OscillatorParams& params, const std::vector<double>& a_u,
                               double x0_m, double v0_m_per_s) {
  OscillatorParams checked = params;
  checked.integrator = Integrator::exact;
  DiscreteModel model;  // only the validation is used; the solution below is independent of it
  const ConfigResult configured = discretise(checked, model);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  if (a_u.empty()) throw HostError("reference solver: the input has no samples");
  for (std::size_t n = 0; n < a_u.size(); ++n) {
    if (!std::isfinite(a_u[n])) {
      throw HostError(fmt::format("reference solver: a_u[{}] = {} is not finite", n, a_u[n]));
    }
  }
  if (!std::isfinite(x0_m) || !std::isfinite(v0_m_per_s)) {
    throw HostError(
        fmt::format("reference solver: the initial state x0 = {} m, v0 = {} m/s is "
                    "not finite",
                    x0_m, v0_m_per_s));
  }
  Solver solver(checked, a_u);
  return solver.run(x0_m, v0_m_per_s);
}

}  // namespace stickslip::host
