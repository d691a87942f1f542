// The seat oscillator with dry friction, stepped one input sample at a time.
//
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u,     a_x = -(k x_r + b v_r + F_f)/m
//
// a_u is piecewise linear between samples (first-order hold); step(a_u[n]) integrates from
// t[n-1] to t[n] using a_u[n-1] (kept from the previous call) and a_u[n] only: causal.
//
// The linear part of every integrator is a precomputed affine map (see step_map.hpp); the step
// does no division and calls no transcendental function except the friction law's own
// (atan/tanh/erf/exp) and the in-step event interpolation (rare path).
//
// Stick-slip: while slipping, a sign change of v_r inside the step is located by bisection on a
// dyadic grid of the step (maps for dt/2^l are precomputed) and linear interpolation in the last
// tick; there the limit force F_L = -(m a_u + k x_r) decides stick (|F_L| <= F_fs) or reversal.
// While stuck, F_L is linear in time inside the step, so the break-away instant is found in closed
// form. The rest of the step is integrated in the new mode; several events per step are handled.
#pragma once

#include <cstdint>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/integrators/step_map.hpp"

namespace stickslip {

template <typename T>
struct StepOutput {
  T x_r_m;           // relative displacement at the end of the step
  T v_r_m_per_s;     // relative velocity
  T a_x_m_per_s2;    // absolute seat acceleration; equals a_u exactly while stuck
  T friction_n;      // friction force F_f on the seat (the holding force while stuck)
  T stuck_time_s;    // time spent stuck inside this step
  T stuck_fraction;  // the same as a fraction of the step, in [0, 1] (exact sums in float too)
  bool stuck;        // stuck at the end of the step
  std::uint8_t events;  // stick, break-away and reversal events inside this step
};

// Safety limit on events inside one step; beyond it the step finishes in its current mode. Keeps
// the worst-case time of step() bounded; counted in event_budget_exhausted().
inline constexpr int kMaxEventsPerStep = 32;

template <typename T, typename Law>
class Oscillator {
  using S = ScalarTraits<T>;

 public:
  using Scalar = T;
  using FrictionLaw = Law;

  // Validates the parameters and precomputes every coefficient. The model in `params` must match
  // Law (checked); the oscillator is left reset to rest with a_u = 0.
  ConfigResult configure(const OscillatorParams& params) noexcept {
    DiscreteModel model;
    ConfigResult result = discretise(params, model);
    if (result.ok() && params.model != Law::model) {
      result.status = Status::unsupported;
      result.message.clear();
      result.message.append("model: oscillator instantiated for '")
          .append(model_name(Law::model))
          .append("' cannot run '")
          .append(model_name(params.model))
          .append("'");
    }
    if (!result.ok()) return result;
    for (int level = 0; level < kMapLevels; ++level) {
      maps_[level] = StepMap<T>::from_double(model.maps[level]);
      block_s_[level] = S::from_double(model.block_s[level]);
    }
    dt_s_ = S::from_double(params.dt_s);
    tick_s_ = block_s_[kEventLevels];
    inv_dt_ = S::from_double(model.inv_dt);
    mass_kg_ = S::from_double(params.mass_kg);
    stiffness_ = S::from_double(params.stiffness_n_per_m);
    inv_mass_ = S::from_double(model.inv_mass);
    k_over_m_ = S::from_double(model.stiffness_over_mass);
    b_over_m_ = S::from_double(model.damping_over_mass);
    friction_.kinetic_n = S::from_double(params.kinetic_friction_n);
    friction_.static_n = S::from_double(params.static_friction_n);
    friction_.stribeck_excess_n = S::from_double(model.stribeck_excess_n);
    friction_.inv_stribeck_velocity = S::from_double(model.inv_stribeck_velocity);
    friction_.smoothing_c = S::from_double(params.smoothing_constant_s_per_m);
    friction_.smoothing_scale_n = S::from_double(model.smoothing_scale_n);
    const bool rk4 = params.integrator == Integrator::rk4;
    if constexpr (Law::kind == LawKind::none) {
      stage_friction_ = false;
      held_events_ = false;
    } else {
      stage_friction_ = rk4 && Law::velocity_dependent;
      held_events_ = params.integrator == Integrator::exact;
    }
    reset(T(0), T(0), T(0));
    return result;
  }

  // Initial state x_r = x0, v_r = v0 with the input at a_u0. A sticking law starts stuck when
  // v0 = 0 and |F_L(0)| <= F_fs; otherwise it slips in the direction of v0 (or of F_L).
  void reset(T x0_m, T v0_m_per_s, T a_u0) noexcept {
    x_ = x0_m;
    v_ = v0_m_per_s;
    a_prev_ = a_u0;
    event_budget_exhausted_ = 0;
    rejected_inputs_ = 0;
    state_resets_ = 0;
    if constexpr (Law::kind == LawKind::held) {
      held_force_ = Law::force(v_, friction_);
      reported_force_ = held_force_;
    } else if constexpr (Law::kind == LawKind::sticking) {
      const T limit = limit_force(a_u0, x_);
      if (v_ == T(0)) {
        direction_ = S::abs(limit) <= friction_.static_n ? T(0) : signum(limit);
      } else {
        direction_ = signum(v_);
      }
    }
  }

  // The outputs for the current state (the first row of a simulation, before any step).
  StepOutput<T> current() const noexcept { return output(a_prev_, T(0), 0); }

  // Advances one sample: from the previous input a_u[n-1] to a_u_next = a_u[n].
  // A non-finite input is replaced by the previous one and counted in rejected_inputs().
  StepOutput<T> step(T a_u_next) noexcept {
    if (!S::is_finite(a_u_next)) {
      a_u_next = a_prev_;
      ++rejected_inputs_;
    }
    const Input in{a_prev_, a_u_next};
    T stuck_fraction = T(0);
    int events = 0;

    if constexpr (Law::kind == LawKind::none) {
      advance_affine(x_, v_, 0, -in.a0, -in.a1);
    } else if constexpr (Law::kind == LawKind::held) {
      events = step_held(in);
    } else {
      events = step_sticking(in, stuck_fraction);
    }
    a_prev_ = a_u_next;
    guard_state();
    return output(a_u_next, stuck_fraction, events);
  }

  T x_r() const noexcept { return x_; }
  T v_r() const noexcept { return v_; }
  bool stuck() const noexcept {
    if constexpr (Law::kind == LawKind::sticking) return direction_ == T(0);
    return false;
  }
  T dt_s() const noexcept { return dt_s_; }
  // Steps that hit kMaxEventsPerStep (should stay 0; a non-zero count means a degenerate scene).
  std::uint64_t event_budget_exhausted() const noexcept { return event_budget_exhausted_; }
  // Non-finite input samples replaced by the previous sample.
  std::uint64_t rejected_inputs() const noexcept { return rejected_inputs_; }
  // Times the non-finite guard restarted the state from rest (0 for any accepted configuration).
  std::uint64_t state_resets() const noexcept { return state_resets_; }

 private:
  // Input over the current step, linear in the fraction of the step phi in [0, 1].
  struct Input {
    T a0, a1;
    T at(T phi) const noexcept { return (T(1) - phi) * a0 + phi * a1; }  // exact at both ends
  };
  // Position inside the step: whole ticks of dt/2^kEventLevels plus a fraction of the next tick.
  struct Position {
    unsigned tick;
    T frac;
    T phi() const noexcept { return (T(tick) + frac) * kInvTicks; }
  };
  struct ConstantForce {
    T force_n;
    T operator()(T /*v*/) const noexcept { return force_n; }
  };
  struct SlipForce {
    const FrictionCoefficients<T>* coefficients;
    T direction;
    T operator()(T v) const noexcept { return Law::slip_force(v, direction, *coefficients); }
  };

  static constexpr T kInvTicks = T(1) / T(kTicksPerStep);  // exact: a power of two
  static constexpr T kHalf = T(0.5);

  T limit_force(T a_u, T x) const noexcept { return -(mass_kg_ * a_u + stiffness_ * x); }

  // dv_r/dt for a given friction force.
  T relative_acceleration(T x, T v, T force_n, T a_u) const noexcept {
    return -(k_over_m_ * x + b_over_m_ * v + inv_mass_ * force_n) - a_u;
  }

  void advance_affine(T& x, T& v, int level, T g0, T g1) const noexcept {
    const StepMap<T>& m = maps_[level];
    const T x_next = m.xx * x + m.xv * v + m.gx0 * g0 + m.gx1 * g1;
    const T v_next = m.vx * x + m.vv * v + m.gv0 * g0 + m.gv1 * g1;
    x = x_next;
    v = v_next;
  }

  // Classic RK4 with the friction force evaluated at every stage (velocity-dependent laws).
  template <typename Force>
  void advance_rk4(T& x, T& v, int level, T a_u0, T a_u1, const Force& force) const noexcept {
    const T h = block_s_[level];
    const T half_h = kHalf * h;
    const T a_mid = kHalf * (a_u0 + a_u1);
    const T k1x = v;
    const T k1v = relative_acceleration(x, v, force(v), a_u0);
    const T x2 = x + half_h * k1x, v2 = v + half_h * k1v;
    const T k2v = relative_acceleration(x2, v2, force(v2), a_mid);
    const T x3 = x + half_h * v2, v3 = v + half_h * k2v;
    const T k3v = relative_acceleration(x3, v3, force(v3), a_mid);
    const T x4 = x + h * v3, v4 = v + h * k3v;
    const T k4v = relative_acceleration(x4, v4, force(v4), a_u1);
    const T sixth_h = h * (T(1) / T(6));
    x = x + sixth_h * (k1x + T(2) * (v2 + v3) + v4);
    v = v + sixth_h * (k1v + T(2) * (k2v + k3v) + k4v);
  }

  // One block of 2^(kEventLevels - level) ticks starting at `tick`.
  template <typename Force>
  void advance_block(T& x, T& v, unsigned tick, int level, const Input& in,
                     const Force& force) const noexcept {
    const unsigned size = kTicksPerStep >> level;
    const T a_u0 = in.at(T(tick) * kInvTicks);
    const T a_u1 = in.at(T(tick + size) * kInvTicks);
    if (stage_friction_) {
      advance_rk4(x, v, level, a_u0, a_u1, force);
    } else {
      // Friction held over the block at its value at the block start.
      const T scaled_force = inv_mass_ * force(v);
      advance_affine(x, v, level, -(a_u0 + scaled_force), -(a_u1 + scaled_force));
    }
  }

  static int lowest_set_bit(unsigned value) noexcept {
    int bit = 0;
    while ((value & 1u) == 0u) {
      value >>= 1u;
      ++bit;
    }
    return bit;
  }

  // Integrates from `pos` to the end of the step with the given friction. With direction d != 0,
  // stops at the first instant where v_r*d turns negative: returns true with v_r = 0 and `pos` at
  // that instant. d = 0 integrates to the end without looking for events.
  // `starting`: the slip phase begins here (break-away or reversal), where a_r*d >= 0 by the stick
  // decision; its first tick cannot hold a genuine crossing, so v_r*d is clamped at 0 there
  // instead of letting rounding (a_r ~ 0 when |F_L| ~ F_fs) fake one.
  template <typename Force>
  bool slip(Position& pos, T& x, T& v, T d, const Input& in, const Force& force,
            bool starting = false) const noexcept {
    if (pos.tick < kTicksPerStep && (pos.frac > T(0) || starting)) {
      // Finish the tick we are inside, with a second-order Taylor step.
      const T h = (T(1) - pos.frac) * tick_s_;
      const T f = force(v);
      const T a = relative_acceleration(x, v, f, in.at(pos.phi()));
      const T jerk = -(k_over_m_ * v + b_over_m_ * a) - (in.a1 - in.a0) * inv_dt_;
      const T x_end = x + h * (v + kHalf * a * h);
      T v_end = v + h * (a + kHalf * jerk * h);
      if (starting && v_end * d < T(0)) v_end = T(0);
      if (v_end * d < T(0)) {
        const T theta = v / (v - v_end);
        x = x + theta * (x_end - x);
        v = T(0);
        pos.frac = pos.frac + theta * (T(1) - pos.frac);
        if (!(pos.frac < T(1))) {
          ++pos.tick;
          pos.frac = T(0);
        }
        return true;
      }
      x = x_end;
      v = v_end;
      ++pos.tick;
      pos.frac = T(0);
    }
    while (pos.tick < kTicksPerStep) {
      // The largest dyadic block aligned at pos.tick (the whole step from the start).
      int level = pos.tick == 0u ? 0 : kEventLevels - lowest_set_bit(pos.tick);
      const T a_start =
          relative_acceleration(x, v, force(v), in.at(T(pos.tick) * kInvTicks));
      for (;;) {
        const unsigned size = kTicksPerStep >> level;
        T x_end = x, v_end = v;
        advance_block(x_end, v_end, pos.tick, level, in, force);
        const bool crossed = v_end * d < T(0);
        bool dip = false;  // |v| fell and rose again inside the block: it may have crossed twice
        if (!crossed && a_start * d < T(0)) {
          const T a_end = relative_acceleration(x_end, v_end, force(v_end),
                                                in.at(T(pos.tick + size) * kInvTicks));
          dip = a_end * d > T(0);
        }
        if (!crossed && (!dip || level == kEventLevels)) {
          x = x_end;
          v = v_end;
          pos.tick += size;
          break;
        }
        if (level == kEventLevels && crossed) {
          const T theta = v / (v - v_end);  // linear inside one tick
          x = x + theta * (x_end - x);
          v = T(0);
          pos.frac = theta;
          if (!(theta < T(1))) {
            ++pos.tick;
            pos.frac = T(0);
          }
          return true;
        }
        ++level;  // bisect: try the first half
      }
    }
    return false;
  }

  // Held laws (signum, smoothed): friction from the state at the start of the step. With the exact
  // integrator a sign change of v_r inside the step is located and the friction re-sampled there
  // with the law's value at rest (signum: the Filippov value clamp(F_L, +-F_fk), i.e. hold the load
  // or reverse against it; smoothed: 0). Friction then never does positive work: the scheme is
  // passive. Explicit integrators follow Simulink ode1 (no event location).
  int step_held(const Input& in) noexcept {
    int events = 0;
    T force = held_force_;
    if (stage_friction_) {
      advance_rk4(x_, v_, 0, in.a0, in.a1,
                  [this](T v) noexcept { return Law::force(v, friction_); });
    } else if (held_events_ && force != T(0)) {
      Position pos{0u, T(0)};
      T d = signum(v_);
      bool starting = false;
      while (slip(pos, x_, v_, d, in, ConstantForce{force}, starting)) {
        ++events;
        force = Law::force_at_rest(limit_force(in.at(pos.phi()), x_), friction_);
        // Slipping again only if the friction saturates against the load; otherwise held at rest
        // for the rest of the step (no further events to look for).
        const bool saturated = S::abs(force) == friction_.kinetic_n && force != T(0);
        d = saturated && events < kMaxEventsPerStep ? signum(force) : T(0);
        starting = d != T(0);
      }
    } else {
      const T scaled_force = inv_mass_ * force;
      advance_affine(x_, v_, 0, -(in.a0 + scaled_force), -(in.a1 + scaled_force));
    }
    held_force_ = Law::force(v_, friction_);
    // Reported at the sample: with events, the friction acting at the end of the step (the
    // trajectory's own); otherwise the law at the sample, as ode1 reports it.
    reported_force_ = held_events_ ? force : held_force_;
    return events;
  }

  // Stick-slip and Stribeck: the event loop of one step.
  int step_sticking(const Input& in, T& stuck_fraction) noexcept {
    Position pos{0u, T(0)};
    int events = 0;
    bool starting = false;  // a slip phase begins at pos (after break-away or reversal)
    for (;;) {
      if (direction_ == T(0)) {
        // Stuck: F_L is linear in time inside the step; check the end, then solve for break-away.
        const T limit_end = limit_force(in.a1, x_);
        const T phi_now = pos.phi();
        if (S::abs(limit_end) <= friction_.static_n || events >= kMaxEventsPerStep) {
          if (events >= kMaxEventsPerStep) ++event_budget_exhausted_;
          stuck_fraction += T(1) - phi_now;
          return events;
        }
        const T limit_now = limit_force(in.at(phi_now), x_);
        const T d = signum(limit_end);
        // |F_L| crosses F_fs between now and the end; the denominator is non-zero because
        // |limit_now| < F_fs < |limit_end| (at or above F_fs already: break away now).
        T ratio = T(0);
        if (S::abs(limit_now) < friction_.static_n) {
          ratio = (d * friction_.static_n - limit_now) / (limit_end - limit_now);
          ratio = ratio < T(0) ? T(0) : (ratio > T(1) ? T(1) : ratio);
        }
        const T phi_break = phi_now + ratio * (T(1) - phi_now);
        stuck_fraction += phi_break - phi_now;
        const T ticks = phi_break * T(kTicksPerStep);
        unsigned whole = static_cast<unsigned>(ticks);
        if (whole >= kTicksPerStep) whole = kTicksPerStep;
        pos.tick = whole;
        pos.frac = whole >= kTicksPerStep ? T(0) : ticks - T(whole);
        direction_ = d;
        v_ = T(0);
        ++events;
        starting = true;
        continue;
      }
      const bool detect = events < kMaxEventsPerStep;
      if (!detect) ++event_budget_exhausted_;
      const T d = detect ? direction_ : T(0);
      if (!slip(pos, x_, v_, d, in, SlipForce{&friction_, direction_}, starting)) return events;
      ++events;
      // v_r reached 0: stick if the limit force is within static friction, else reverse.
      const T limit = limit_force(in.at(pos.phi()), x_);
      direction_ = S::abs(limit) <= friction_.static_n ? T(0) : signum(limit);
      starting = direction_ != T(0);
    }
  }

  StepOutput<T> output(T a_u, T stuck_fraction, int events) const noexcept {
    StepOutput<T> out{};
    out.x_r_m = x_;
    out.v_r_m_per_s = v_;
    out.stuck_time_s = stuck_fraction * dt_s_;
    out.stuck_fraction = stuck_fraction;
    out.events = static_cast<std::uint8_t>(events);
    out.stuck = false;
    T force = T(0);
    if constexpr (Law::kind == LawKind::held) {
      force = reported_force_;
    } else if constexpr (Law::kind == LawKind::sticking) {
      if (direction_ == T(0)) {
        out.stuck = true;
        out.friction_n = limit_force(a_u, x_);  // the force that holds the seat
        out.a_x_m_per_s2 = a_u;                 // moves with the floor, exactly
        return out;
      }
      force = Law::slip_force(v_, direction_, friction_);
    }
    out.friction_n = force;
    out.a_x_m_per_s2 = -(k_over_m_ * x_ + b_over_m_ * v_ + inv_mass_ * force);
    return out;
  }

  // A running model never emits NaN/Inf: should the state ever leave the finite range (it cannot
  // for an accepted configuration and finite input), restart from rest and count it.
  void guard_state() noexcept {
    if (S::is_finite(x_) && S::is_finite(v_)) return;
    x_ = T(0);
    v_ = T(0);
    ++state_resets_;
    if constexpr (Law::kind == LawKind::held) held_force_ = reported_force_ = T(0);
    if constexpr (Law::kind == LawKind::sticking) direction_ = T(0);
  }

  // Coefficients (read-only after configure).
  StepMap<T> maps_[kMapLevels]{};
  T block_s_[kMapLevels]{};
  T dt_s_{}, tick_s_{}, inv_dt_{}, mass_kg_{}, stiffness_{}, inv_mass_{}, k_over_m_{}, b_over_m_{};
  FrictionCoefficients<T> friction_{};
  bool stage_friction_ = false;  // RK4 with the friction law evaluated at every stage
  bool held_events_ = false;     // exact integrator: locate sign changes of held friction

  // State.
  T x_{}, v_{}, a_prev_{};
  T held_force_{};      // held laws: friction at the start of the next step
  T reported_force_{};  // held laws: friction reported with the sample
  T direction_{};   // sticking laws: 0 stuck, +1/-1 slipping
  std::uint64_t event_budget_exhausted_ = 0;
  std::uint64_t rejected_inputs_ = 0;
  std::uint64_t state_resets_ = 0;
};

}  // namespace stickslip
