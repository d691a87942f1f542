// The reference solver's event driver (reference_solver.hpp): the state between samples, the
// per-sample loop and the events, with the per-law segment solvers it calls: the sticking laws'
// closed-form stuck and slip phases (reference_coulomb_segments.cpp) and the adaptive integration
// of the Stribeck and smooth laws (reference_ode_segments.cpp). Private to the run library.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <fmt/format.h>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>

#include "reference_checks.hpp"
#include "reference_closed_form.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/reference_solver.hpp"

namespace stickslip::host::reference {

namespace odeint = boost::numeric::odeint;

// Step tolerances of the adaptive integration (Stribeck, smooth laws).
constexpr double kOdeRelativeTolerance = 1e-15;
constexpr double kOdeAbsoluteTolerance = 1e-18;  // m and m/s
constexpr int kMaxRejectedSteps = 200;
// Near v_r = 0 (|v_r| below kVelocityBand velocity scales of the law) a step may change v_r by at
// most kVelocityResolution scales.
constexpr double kVelocityBand = 20.0;
constexpr double kVelocityResolution = 0.1;

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
  // f_a_n: the actuator force held over each sample interval (f_a_n[n] from t[n-1] to t[n]), or
  // nullptr for none.
  Solver(const OscillatorParams& p, const std::vector<double>& a_u,
         const std::vector<double>* f_a_n = nullptr)
      : p_(p),
        a_u_(a_u),
        f_a_(f_a_n),
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

  ReferenceTrace run(double x0, double v0);

 private:
  Real limit_force(Real a_u) const { return -(mass_ * a_u + stiffness_ * x_); }
  // f_a[n]/m: a force held over the interval is a constant shift of its input a_u -> a_u - f_a/m.
  Real force_offset(std::size_t n) const {
    return f_a_ == nullptr ? Real(0) : wide((*f_a_)[n]) / mass_;
  }
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
    const Real offset = force_offset(n);
    trace.x_r_m[n] = narrow(x_);
    trace.v_r_m_per_s[n] = narrow(v_);
    if (direction_ == 0) {  // stuck: the friction holds F_L and the seat moves with the floor
      trace.friction_n[n] = narrow(limit_force(a_u - offset));
      trace.a_x_m_per_s2[n] = a_u_[n];
      trace.stuck[n] = 1;
      return;
    }
    const Real force = wide(friction(static_cast<double>(v_), static_cast<double>(direction_)));
    trace.friction_n[n] = narrow(force);
    trace.a_x_m_per_s2[n] = narrow(offset - (stiffness_ * x_ + damping_ * v_ + force) / mass_);
    trace.stuck[n] = 0;
  }

  void count_event(int& events_in_sample) {
    ++events_;
    count_sample_event(events_in_sample, sample_, p_.dt_s);
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
  Real stuck_until(Real a0, Real a1, Real tau, int& events_in_sample);

  void advance_linear(Real a0, Real a1) {
    const RampMotion motion(modes_, x_, v_, a0, (a1 - a0) / dt_, 0);
    const Kinematics end = motion.at(full_sample_, dt_);
    x_ = end.x;
    v_ = end.v;
  }

  // One sample interval of a sticking law: stuck phases in closed form, slip phases in closed form
  // (Coulomb) or by the adaptive integrator (Stribeck), as many events as occur.
  void advance_sticking(Real a0, Real a1);

  // Coulomb slip from tau with friction F_fk d: the closed form, searched piece by piece for the
  // first v_r = 0 instant. Leaves the state at the event (tau_event) or at the sample end.
  Crossing slip_closed_form(Real a0, Real a1, Real slope, Real tau, Real& tau_event);

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
  Kinematics kinematics(const OdeSystem& system, const OdeState& s, double t) const;

  // One accepted adaptive step from t (capped at t_end); returns the new time.
  double ode_step(const OdeSystem& system, const OdeState& from, double t, double t_end,
                  OdeState& to);

  // Stribeck slip from tau in direction d, adaptively, with the event search inside each step.
  Crossing slip_ode(Real a0, Real a1, Real tau, Real& tau_event);

  // Smooth laws: no events. The rational form c v/(1 + c|v|) has a jump in its second derivative
  // at v_r = 0, which costs a Runge-Kutta step its order: steps are ended at the v_r = 0 instants
  // (found like the events of the sticking laws), so that no step integrates across the kink.
  void advance_smooth();

  const OscillatorParams& p_;
  const std::vector<double>& a_u_;
  const std::vector<double>* f_a_ = nullptr;
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

}  // namespace stickslip::host::reference
