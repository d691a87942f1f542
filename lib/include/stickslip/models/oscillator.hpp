// The seat oscillator with dry friction, stepped one input sample at a time.
//
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u,     a_x = -(k x_r + b v_r + F_f)/m
//
// a_u is piecewise linear between samples (first-order hold); step(a_u[n]) integrates from
// t[n-1] to t[n] using a_u[n-1] (kept from the previous call) and a_u[n] only: causal.
//
// The linear part of every integrator is a precomputed affine map (see step_map.hpp); the step
// does no division and calls no transcendental function except the friction law's own
// (atan/tanh/erf/exp) and the in-step event location (ScalarTraits::proportion(): a division in
// floating point, shift-and-subtract in fixed point; rare path). Its common path (whole step
// stuck, or slipping without a sign change) is inline and branch-light; the event search is out
// of line.
//
// Stick-slip: while slipping, a sign change of v_r inside the step is located by bisection on a
// dyadic grid of the step (maps for dt/2^l are precomputed) down to a "tick", inside which the
// exact integrator solves the Taylor polynomial of the exact solution and the other integrators
// interpolate linearly (ticks of dt/2^16); there the limit force F_L = -(m a_u + k x_r) decides
// stick (|F_L| <= F_fs) or reversal.
// While stuck, F_L is linear in time inside the step, so the break-away instant is found in closed
// form. The rest of the step is integrated in the new mode; several events per step are handled.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/integrators/fixed_point_scaling.hpp"
#include "stickslip/integrators/step_map.hpp"
#include "stickslip/integrators/taylor_segment.hpp"
#include "stickslip/models/whole_step.hpp"

namespace stickslip {

template <typename T>
struct StepOutput {
  T x_r_m;              // relative displacement at the end of the step
  T v_r_m_per_s;        // relative velocity
  T a_x_m_per_s2;       // absolute seat acceleration; equals a_u exactly while stuck
  T friction_n;         // friction force F_f on the seat (the holding force while stuck)
  T stuck_time_s;       // time spent stuck inside this step
  T stuck_fraction;     // the same as a fraction of the step, in [0, 1] (exact sums in float too)
  bool stuck;           // stuck at the end of the step
  std::uint8_t events;  // stick, break-away and reversal events inside this step
};

template <typename T, std::size_t N>
class StickSlipBatch;

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
    if constexpr (S::kTracksSaturation) {
      // Fixed point: the scene's coefficients and intermediates must fit the format.
      if (result.ok()) {
        result = check_fixed_point_scene(params, model, T::kIntegerBits, T::kFractionBits,
                                         S::kEventTickLevel);
      }
    }
    if (!result.ok()) return result;
    for (int level = 0; level < kMapLevels; ++level) {
      maps_[level] = StepMap<T>::from_double(model.maps[level]);
      block_s_[level] = S::from_double(model.block_s[level]);
    }
    dt_s_ = S::from_double(params.dt_s);
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
    // The event search: bisection down to ticks of dt / 2^event_level_, then the Taylor
    // polynomial of the exact solution (exact integrator) or linear interpolation inside a tick.
    // (A fixed-point scalar always bisects and interpolates, in ticks of its own size.)
    EventSearchPlan plan{kEventLevels, 0};
    if constexpr (S::kTaylorEventSearch) {
      plan = event_search_plan(params, S::to_double(ScalarTraits<T>::epsilon()));
    } else {
      plan = EventSearchPlan{S::kEventTickLevel, 0};
    }
    event_level_ = plan.tick_level;
    ticks_per_step_ = 1u << plan.tick_level;
    inv_ticks_ = S::from_double(1.0 / static_cast<double>(ticks_per_step_));  // a power of two
    tick_s_ = block_s_[event_level_];
    // The first 1/2^kEventLevels of the step after a slip starts (see slip()), in ticks.
    start_guard_ticks_ =
        S::from_double(static_cast<double>(ticks_per_step_) / static_cast<double>(kTicksPerStep));
    taylor_ = TaylorCoefficients<T>{};
    taylor_.order = plan.taylor_order;
    if constexpr (S::kTaylorEventSearch) {
      fill_taylor_coefficients(taylor_, model.block_s[event_level_], model.stiffness_over_mass,
                               model.damping_over_mass);
    }
    reset(T(0), T(0), T(0));
    if constexpr (S::kTracksSaturation) {
      // The conversions above fit (checked); start the run with a clear flag.
      (void)S::take_saturation();
      saturated_steps_ = 0;
    }
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
    saturated_steps_ = 0;
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
    slip_a_x_ = current().a_x_m_per_s2;
  }

  // The outputs for the current state (the first row of a simulation, before any step).
  StepOutput<T> current() const noexcept { return output(a_prev_, T(0), 0); }

  // Advances one sample: from the previous input a_u[n-1] to a_u_next = a_u[n].
  // A non-finite input is replaced by the previous one and counted in rejected_inputs().
  STICKSLIP_INLINE_STEP StepOutput<T> step(T a_u_next) noexcept {
    StepOutput<T> out;
    step(a_u_next, out);
    return out;
  }
  // The same, writing the outputs in place: an MCU keeps them in a static record, and the step
  // then holds no copy of them on its stack.
  STICKSLIP_INLINE_STEP void step(T a_u_next, StepOutput<T>& out) noexcept {
    step_unchecked(a_u_next, out);
    if constexpr (S::kTracksSaturation) {
      // Fixed point: every operation of this step that saturated set the sticky flag (so did
      // the caller's conversion of a_u_next, if it did not fit): count the step.
      if (S::take_saturation()) ++saturated_steps_;
    }
  }

 private:
  // Every path fills `out` in place (no temporary copies of it: 28 bytes each on the M0+, whose
  // stack is the scarce resource).
  STICKSLIP_INLINE_STEP void step_unchecked(T a_u_next, StepOutput<T>& out) noexcept {
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
      // The common paths first, inline: a whole step stuck, or (constant kinetic friction) a
      // whole step slipping without a sign change of v_r. Anything else runs the event search.
      if (direction_ == T(0)) {
        const T limit = stuck_limit_force(mass_kg_, stiffness_, x_, in.a1);
        if (!stuck_step_breaks_away(limit, friction_.static_n)) {
          a_prev_ = a_u_next;
          write_stuck_output(out, a_u_next, limit);
          return;
        }
        events = step_sticking(in, stuck_fraction, nullptr);
      } else if constexpr (!Law::velocity_dependent && S::kCompactStack) {
        if (whole_step_slips(in, out)) {
          a_prev_ = a_u_next;
          return;
        }
        events = step_sticking(in, stuck_fraction, nullptr);
      } else if constexpr (!Law::velocity_dependent) {
        const T force = Law::slip_force(v_, direction_, friction_);
        // inv_mass_ * force, as seat_acceleration() forms it (bit for bit the same value).
        const WholeSlip<T> moved = whole_step_slip(
            maps_[0], k_over_m_, b_over_m_, inv_mass_ * force, x_, v_, slip_a_x_, in.a0, in.a1);
        if (!slip_step_has_event(moved, direction_)) {
          x_ = moved.x;
          v_ = moved.v;
          slip_a_x_ = moved.seat_acceleration;
          a_prev_ = a_u_next;
          write_slip_output(out, force, moved.seat_acceleration);
          return;
        }
        // The search starts from this whole step instead of computing it again.
        events = step_sticking(in, stuck_fraction, &moved);
      } else {
        events = step_sticking(in, stuck_fraction, nullptr);
      }
    }
    a_prev_ = a_u_next;
    guard_state();
    write_output(out, a_u_next, stuck_fraction, events);
    slip_a_x_ = out.a_x_m_per_s2;  // the seat acceleration the next step starts from, if slipping
  }

 public:
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
  // Fixed point: steps in which an operation saturated (always 0 for float and double). Non-zero
  // means the scene left the ranges configure() checked (OscillatorParams::input_range_m_per_s2,
  // displacement_range_m): the outputs of those steps are clipped, not wrapped.
  std::uint64_t saturated_steps() const noexcept { return saturated_steps_; }
  bool saturated() const noexcept { return saturated_steps_ != 0; }

  // The mutable state between two steps (the counters apart), for a caller that keeps many
  // oscillators' states elsewhere (StickSlipBatch) or checkpoints a run. restore() takes a state
  // that state() returned for an oscillator with the same parameters.
  struct State {
    T x_r_m, v_r_m_per_s;
    T a_u_previous;      // the input sample the next step starts from
    T direction;         // sticking laws: 0 stuck, +1/-1 slipping
    T held_force_n;      // held laws: friction at the start of the next step
    T reported_force_n;  // held laws: friction reported with the sample
  };
  State state() const noexcept {
    return {x_, v_, a_prev_, direction_, held_force_, reported_force_};
  }
  void restore(const State& s) noexcept {
    x_ = s.x_r_m;
    v_ = s.v_r_m_per_s;
    a_prev_ = s.a_u_previous;
    direction_ = s.direction;
    held_force_ = s.held_force_n;
    reported_force_ = s.reported_force_n;
    slip_a_x_ = current().a_x_m_per_s2;
  }

 private:
  // The batch copies the coefficients of its lanes' common path (models/batch.hpp).
  template <typename, std::size_t>
  friend class StickSlipBatch;

  // Input over the current step, linear in the fraction of the step phi in [0, 1].
  struct Input {
    T a0, a1;
    T at(T phi) const noexcept { return (T(1) - phi) * a0 + phi * a1; }  // exact at both ends
  };
  // Position inside the step: whole ticks of dt/2^event_level_ plus a fraction of the next tick.
  struct Position {
    unsigned tick;
    T frac;
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

  static constexpr T kHalf = T(0.5);

  // The exact integrator's Taylor event search (never for a fixed-point scalar: known at compile
  // time, so that its code is not in the fixed-point step).
  bool taylor_search() const noexcept {
    if constexpr (S::kTaylorEventSearch) {
      return taylor_.order > 0;
    } else {
      return false;
    }
  }

  T phi(const Position& pos) const noexcept { return (T(pos.tick) + pos.frac) * inv_ticks_; }

  T limit_force(T a_u, T x) const noexcept { return -(mass_kg_ * a_u + stiffness_ * x); }

  // dv_r/dt for a given friction force.
  T relative_acceleration(T x, T v, T force_n, T a_u) const noexcept {
    return seat_acceleration(k_over_m_, b_over_m_, inv_mass_, x, v, force_n) - a_u;
  }

  void advance_affine(T& x, T& v, int level, T g0, T g1) const noexcept {
    apply_step_map(maps_[level], x, v, g0, g1);
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

  // One block of 2^(event_level_ - level) ticks starting at `tick`.
  template <typename Force>
  void advance_block(T& x, T& v, unsigned tick, int level, const Input& in,
                     const Force& force) const noexcept {
    const unsigned size = ticks_per_step_ >> level;
    const T a_u0 = in.at(T(tick) * inv_ticks_);
    const T a_u1 = in.at(T(tick + size) * inv_ticks_);
    // (Known false at compile time for a law without velocity dependence: no RK4 code in its
    // step.)
    if (Law::velocity_dependent && stage_friction_) {
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

  // The rounding of v_r over a block of `level` started near rest: 8 ulp of the velocity change
  // each acceleration term alone would make (spring, friction, input at both ends) over it.
  T rest_rounding_velocity(int level, T x, T force_n, T a_u_start, const Input& in) const noexcept {
    const T terms = S::abs(k_over_m_ * x) + S::abs(inv_mass_ * force_n) + S::abs(a_u_start) +
                    S::abs(in.a0) + S::abs(in.a1);
    return T(8) * S::epsilon() * block_s_[level] * terms;
  }

  // The generalised input g = -(a_u + F_f/m) changes by this much per tick (first-order hold).
  T input_slope_per_tick(const Input& in) const noexcept { return -(in.a1 - in.a0) * inv_ticks_; }

  static void advance_within_tick(Position& pos, T fraction) noexcept {
    pos.frac = fraction;
    if (!(pos.frac < T(1))) {
      ++pos.tick;
      pos.frac = T(0);
    }
  }

  // Exact integrator: from `pos` inside a tick (or at a slip start) to the end of that tick on
  // the Taylor polynomial of the exact solution, with the friction force_n held. Returns true
  // with v_r = 0 and `pos` at the first instant where v_r d turns negative (d != 0).
  bool finish_tick_taylor(Position& pos, T& x, T& v, T d, const Input& in, T force_n,
                          bool starting) const noexcept {
    const T scaled_force = inv_mass_ * force_n;
    for (;;) {
      const T u_start = pos.frac;
      const T span = T(1) - u_start;
      const TaylorSegment<T> segment(taylor_, x, v, -(in.at(phi(pos)) + scaled_force),
                                     input_slope_per_tick(in), starting ? d : T(0));
      if (d != T(0)) {
        T lo = T(0);
        T at_lo = v * d;
        if (starting) {
          // A slip phase begins here with a_r d >= 0: within its first 1/2^kEventLevels of the
          // step a sign change can only be rounding (a_r ~ 0 when |F_L| ~ F_fs). v_r is clamped
          // at 0 there instead of letting it fake an event, and the search goes on from there.
          lo = start_guard_ticks_ < span ? start_guard_ticks_ : span;
          at_lo = segment.velocity(lo) * d;
          if (at_lo < T(0)) {
            x = segment.position(lo);
            v = T(0);
            advance_within_tick(pos, u_start + lo);
            if (pos.frac == T(0)) return false;
            starting = false;
            continue;
          }
        }
        T root = T(0);
        if (segment.first_crossing(d, lo, span, at_lo, root)) {
          x = segment.position(root);
          v = T(0);
          advance_within_tick(pos, u_start + root);
          return true;
        }
      }
      x = segment.position(span);
      v = segment.velocity(span);
      ++pos.tick;
      pos.frac = T(0);
      return false;
    }
  }

  // Integrates from `pos` to the end of the step with the given friction. With direction d != 0,
  // stops at the first instant where v_r*d turns negative: returns true with v_r = 0 and `pos` at
  // that instant. d = 0 integrates to the end without looking for events.
  // `starting`: the slip phase begins here (break-away or reversal), where a_r*d >= 0 by the stick
  // decision; its first 1/2^kEventLevels of the step cannot hold a genuine crossing, so v_r*d is
  // clamped at 0 there instead of letting rounding (a_r ~ 0 when |F_L| ~ F_fs) fake one.
  // `whole_step`: the common path's whole step from the start of the step, if it was computed.
  template <typename Force>
  STICKSLIP_COMPACT_INLINE bool slip(Position& pos, T& x, T& v, T d, const Input& in,
                                     const Force& force, bool starting = false,
                                     const WholeSlip<T>* whole_step = nullptr) const noexcept {
    if (pos.tick < ticks_per_step_ && (pos.frac > T(0) || starting)) {
      if (taylor_search()) {
        if (finish_tick_taylor(pos, x, v, d, in, force(v), starting)) return true;
      } else {
        // Finish the tick we are inside, with a second-order Taylor step.
        const T h = (T(1) - pos.frac) * tick_s_;
        const T f = force(v);
        const T a = relative_acceleration(x, v, f, in.at(phi(pos)));
        const T jerk = -(k_over_m_ * v + b_over_m_ * a) - (in.a1 - in.a0) * inv_dt_;
        const T x_end = x + h * (v + kHalf * a * h);
        T v_end = v + h * (a + kHalf * jerk * h);
        if (starting && v_end * d < T(0)) v_end = T(0);
        // At rest to rounding (see the block loop below): 0, not a denormal-bound speck.
        if (S::abs(v) <= rest_rounding_velocity(event_level_, x, f, in.at(phi(pos)), in) &&
            S::abs(v_end) <= rest_rounding_velocity(event_level_, x, f, in.at(phi(pos)), in))
          v_end = T(0);
        if (v_end * d < T(0)) {
          const T theta = S::proportion(v, v - v_end);
          x = x + theta * (x_end - x);
          v = T(0);
          advance_within_tick(pos, pos.frac + theta * (T(1) - pos.frac));
          return true;
        }
        x = x_end;
        v = v_end;
        ++pos.tick;
        pos.frac = T(0);
      }
    }
    while (pos.tick < ticks_per_step_) {
      // The largest dyadic block aligned at pos.tick (the whole step from the start).
      int level = pos.tick == 0u ? 0 : event_level_ - lowest_set_bit(pos.tick);
      const T force_start = force(v);
      const T a_u_start = in.at(T(pos.tick) * inv_ticks_);
      const T a_start = relative_acceleration(x, v, force_start, a_u_start);
      for (;;) {
        const unsigned size = ticks_per_step_ >> level;
        T x_end = x, v_end = v;
        const bool known = whole_step != nullptr && pos.tick == 0u && level == 0;
        if (known) {
          x_end = whole_step->x;
          v_end = whole_step->v;
        } else {
          advance_block(x_end, v_end, pos.tick, level, in, force);
        }
        bool crossed = v_end * d < T(0);
        // Interpolating integrators: a block that starts at rest to rounding (a slip start, or a
        // clamp) with the seat balanced at the break-away limit (a_r ~ 0) ends with a v_r of
        // either sign by rounding alone, and linear interpolation would put an "event" near the
        // block start, spending an event per tick with no progress (float stick-slip and Stribeck
        // scenes exhausted their budget so). A crossing within that rounding is no event: v_r is
        // clamped at 0 (also when it stays positive: a speck of 1e-33 m/s would only feed
        // denormal products, FE_UNDERFLOW in float). A genuine stick still shows once a_r exceeds
        // the rounding of its terms.
        if (taylor_.order == 0) {
          const T rounding = rest_rounding_velocity(level, x, force_start, a_u_start, in);
          if (S::abs(v) <= rounding && S::abs(v_end) <= rounding) {
            v_end = T(0);
            crossed = false;
          }
        }
        bool dip = false;  // |v| fell and rose again inside the block: it may have crossed twice
        if (!crossed && a_start * d < T(0)) {
          const T a_end = known ? whole_step->a_end
                                : relative_acceleration(x_end, v_end, force(v_end),
                                                        in.at(T(pos.tick + size) * inv_ticks_));
          dip = a_end * d > T(0);
        }
        if (crossed || dip) {
          if (level < event_level_) {
            ++level;  // bisect: try the first half
            continue;
          }
          // Inside one tick.
          if (taylor_search()) {
            const TaylorSegment<T> segment(taylor_, x, v, -(a_u_start + inv_mass_ * force_start),
                                           input_slope_per_tick(in), T(0));
            T root = T(0);
            if (segment.first_crossing(d, T(0), T(1), v * d, root)) {
              x = segment.position(root);
              v = T(0);
              advance_within_tick(pos, root);
              return true;
            }
            if (crossed) {  // the polynomial and the map disagree only by rounding: at the end
              x = x_end;
              v = T(0);
              ++pos.tick;
              return true;
            }
          } else if (crossed) {
            const T theta = S::proportion(v, v - v_end);  // linear inside one tick
            x = x + theta * (x_end - x);
            v = T(0);
            advance_within_tick(pos, theta);
            return true;
          }
          // A dip without a crossing: accepted.
        }
        x = x_end;
        v = v_end;
        pos.tick += size;
        break;
      }
    }
    return false;
  }

  // Held laws (signum, smoothed): friction from the state at the start of the step. With the exact
  // integrator a sign change of v_r inside the step is located and the friction re-sampled there
  // with the law's value at rest (signum: the Filippov value clamp(F_L, +-F_fk), i.e. hold the load
  // or reverse against it; smoothed: 0). Friction then never does positive work: the scheme is
  // passive. Explicit integrators follow Simulink ode1 (no event location).
  STICKSLIP_OUT_OF_LINE int step_held(const Input& in) noexcept {
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
        force = Law::force_at_rest(limit_force(in.at(phi(pos)), x_), friction_);
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

  // The common path's whole slipping step, out of line for a scalar that asks for a compact
  // stack (ScalarTraits::kCompactStack: the M0+ build): its temporaries then take no room in the
  // frame on top of which the event search runs, which starts again from the step's start (the
  // same operations, so the same bits). True, with `out`, when the step had no event.
  STICKSLIP_OUT_OF_LINE bool whole_step_slips(const Input& in, StepOutput<T>& out) noexcept {
    const T force = Law::slip_force(v_, direction_, friction_);
    const WholeSlip<T> moved = whole_step_slip(maps_[0], k_over_m_, b_over_m_, inv_mass_ * force,
                                               x_, v_, slip_a_x_, in.a0, in.a1);
    if (slip_step_has_event(moved, direction_)) return false;
    x_ = moved.x;
    v_ = moved.v;
    slip_a_x_ = moved.seat_acceleration;
    write_slip_output(out, force, moved.seat_acceleration);
    return true;
  }

  // Stick-slip and Stribeck: the event loop of one step. `whole_step`: the common path's whole
  // slipping step (Coulomb), when it found an event.
  STICKSLIP_OUT_OF_LINE int step_sticking(const Input& in, T& stuck_fraction,
                                          const WholeSlip<T>* whole_step) noexcept {
    Position pos{0u, T(0)};
    int events = 0;
    bool starting = false;  // a slip phase begins at pos (after break-away or reversal)
    for (;;) {
      if (direction_ == T(0)) {
        // Stuck: F_L is linear in time inside the step; check the end, then solve for break-away.
        const T limit_end = limit_force(in.a1, x_);
        const T phi_now = phi(pos);
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
          ratio = S::proportion(d * friction_.static_n - limit_now, limit_end - limit_now);
          ratio = ratio < T(0) ? T(0) : (ratio > T(1) ? T(1) : ratio);
        }
        const T phi_break = phi_now + ratio * (T(1) - phi_now);
        stuck_fraction += phi_break - phi_now;
        const T ticks = phi_break * T(ticks_per_step_);
        unsigned whole = static_cast<unsigned>(ticks);
        if (whole >= ticks_per_step_) whole = ticks_per_step_;
        pos.tick = whole;
        pos.frac = whole >= ticks_per_step_ ? T(0) : ticks - T(whole);
        direction_ = d;
        v_ = T(0);
        ++events;
        starting = true;
        continue;
      }
      const bool detect = events < kMaxEventsPerStep;
      if (!detect) ++event_budget_exhausted_;
      const T d = detect ? direction_ : T(0);
      if (!slip(pos, x_, v_, d, in, SlipForce{&friction_, direction_}, starting,
                events == 0 ? whole_step : nullptr)) {
        return events;
      }
      ++events;
      // v_r reached 0: stick if the limit force is within static friction, else reverse.
      const T limit = limit_force(in.at(phi(pos)), x_);
      direction_ = S::abs(limit) <= friction_.static_n ? T(0) : signum(limit);
      starting = direction_ != T(0);
    }
  }

  // The outputs of a whole stuck step (no event): the seat moves with the floor. (The write_*
  // functions set every field: no memset of the whole struct.)
  void write_stuck_output(StepOutput<T>& out, T a_u, T holding_force_n) const noexcept {
    out.x_r_m = x_;
    out.v_r_m_per_s = v_;
    out.a_x_m_per_s2 = a_u;
    out.friction_n = holding_force_n;
    out.stuck_time_s = dt_s_;
    out.stuck_fraction = T(1);
    out.stuck = true;
    out.events = 0;
  }

  // The outputs of a whole slipping step (no event), with a_x already computed.
  void write_slip_output(StepOutput<T>& out, T force_n, T a_x) const noexcept {
    out.x_r_m = x_;
    out.v_r_m_per_s = v_;
    out.a_x_m_per_s2 = a_x;
    out.friction_n = force_n;
    out.stuck_time_s = T(0);
    out.stuck_fraction = T(0);
    out.stuck = false;
    out.events = 0;
  }

  StepOutput<T> output(T a_u, T stuck_fraction, int events) const noexcept {
    StepOutput<T> out;
    write_output(out, a_u, stuck_fraction, events);
    return out;
  }

  void write_output(StepOutput<T>& out, T a_u, T stuck_fraction, int events) const noexcept {
    if constexpr (Law::kind == LawKind::none) {
      // No friction element, nothing of it in the output: (1/m) * 0 would still cost a multiply
      // and an add, which floating point may not drop (the linear scene's cost, docs/SCENES.md).
      (void)a_u;
      out.x_r_m = x_;
      out.v_r_m_per_s = v_;
      out.a_x_m_per_s2 = -(k_over_m_ * x_ + b_over_m_ * v_);
      out.friction_n = T(0);
      out.stuck_time_s = T(0);
      out.stuck_fraction = stuck_fraction;
      out.events = static_cast<std::uint8_t>(events);
      out.stuck = false;
      return;
    }
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
        return;
      }
      force = Law::slip_force(v_, direction_, friction_);
    }
    out.friction_n = force;
    out.a_x_m_per_s2 = seat_acceleration(k_over_m_, b_over_m_, inv_mass_, x_, v_, force);
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

  // restore() for a caller that also knows the seat acceleration at that state (the batch).
  void restore(const State& s, T slip_a_x) noexcept {
    x_ = s.x_r_m;
    v_ = s.v_r_m_per_s;
    a_prev_ = s.a_u_previous;
    direction_ = s.direction;
    held_force_ = s.held_force_n;
    reported_force_ = s.reported_force_n;
    slip_a_x_ = slip_a_x;
  }

  // Coefficients (read-only after configure).
  StepMap<T> maps_[kMapLevels]{};
  T block_s_[kMapLevels]{};
  T dt_s_{}, tick_s_{}, inv_dt_{}, mass_kg_{}, stiffness_{}, inv_mass_{}, k_over_m_{}, b_over_m_{};
  FrictionCoefficients<T> friction_{};
  TaylorCoefficients<T> taylor_{};  // exact integrator: the tick's Taylor recurrence
  T inv_ticks_{};                   // 1 / ticks_per_step_
  T start_guard_ticks_{};           // 1/2^kEventLevels of the step, in ticks
  int event_level_ = kEventLevels;  // ticks are blocks of dt / 2^event_level_
  unsigned ticks_per_step_ = kTicksPerStep;
  bool stage_friction_ = false;  // RK4 with the friction law evaluated at every stage
  bool held_events_ = false;     // exact integrator: locate sign changes of held friction

  // State.
  T x_{}, v_{}, a_prev_{};
  T held_force_{};      // held laws: friction at the start of the next step
  T reported_force_{};  // held laws: friction reported with the sample
  T direction_{};       // sticking laws: 0 stuck, +1/-1 slipping
  // Coulomb slip: a_x at the current state with the current slip force (what the previous step
  // reported), the start of the next step's dip test. Unused while stuck.
  T slip_a_x_{};
  std::uint64_t event_budget_exhausted_ = 0;
  std::uint64_t rejected_inputs_ = 0;
  std::uint64_t state_resets_ = 0;
  std::uint64_t saturated_steps_ = 0;
};

}  // namespace stickslip
