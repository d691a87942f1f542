// The seat oscillator with dry friction, stepped one input sample at a time.
//
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u + f_a,     a_x = (f_a - (k x_r + b v_r + F_f))/m
//
// a_u is piecewise linear between samples (first-order hold); step(a_u[n]) integrates from
// t[n-1] to t[n] using a_u[n-1] (kept from the previous call) and a_u[n] only: causal.
// f_a, an actuator force on the seat (upward positive), is held over the step it comes with:
// step(a_u[n], f_a[n]) applies f_a[n] from t[n-1] to t[n]. It shifts the step's input to
// a_u - f_a/m (every integrator's map unchanged, exact stays exact); F_L = f_a - (m a_u + k x_r).
//
// The linear part of every integrator is a precomputed affine map (see step_map.hpp); the step
// does no division and calls no transcendental function except the friction law's own
// (atan/tanh/erf/exp) and the in-step event location (ScalarTraits::proportion(): a division in
// floating point, shift-and-subtract in fixed point; rare path). Its common path (whole step
// stuck, or slipping without a sign change) is inline and branch-light; the event search is out
// of line.
//
// Stick-slip: at an event found inside the step (models/detail/event_search.hpp), the limit force
// F_L = -(m a_u + k x_r) decides stick (|F_L| <= F_fs) or reversal; the rest of the step is
// integrated in the mode that follows, and several events per step are handled.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/integrators/fixed_point_scaling.hpp"
#include "stickslip/integrators/step_map.hpp"
#include "stickslip/integrators/taylor_segment.hpp"
#include "stickslip/models/step_common.hpp"
#include "stickslip/models/whole_step.hpp"

namespace stickslip {

template <typename T, std::size_t N>
class StickSlipBatch;

template <typename T, typename Law>
class Oscillator {
  using S = ScalarTraits<T>;

 public:
  using Scalar = T;
  using FrictionLaw = Law;
  // Events located in one step at most. With a slip force constant over each piece of motion
  // (stick-slip; the held laws; Stribeck, whose force every integrator but RK4 holds at its value
  // where the piece starts), the exact solution's own bound for every step configure() accepts
  // (step_common.hpp). RK4 evaluates Stribeck's force at its stages, so that it follows v_r
  // inside a piece: that configuration keeps the safety limit (kStageFrictionEventBudget;
  // event_budget() is the one in force). At the budget the step finishes in its mode; a step
  // where that lost an event (stuck to the end with |F_L| beyond F_fs, or slipping to the end
  // with v_r against its direction) is counted in event_budget_exhausted(), which by the bound
  // only rounding could reach. A law may declare a smaller budget (`static constexpr int
  // kEventBudget`, 1 or more), for an integrator whose frame cannot afford the bound's events:
  // its steps then lose events, and count them.
  static constexpr int kEventBudget =
      law_detail::event_budget<Law>(kMaxEventsOfTheExactSolutionPerStep);
  static constexpr int kStageFrictionEventBudget =
      law_detail::event_budget<Law>(Law::kind == LawKind::sticking && Law::velocity_dependent
                                        ? kMaxEventsPerStep
                                        : kMaxEventsOfTheExactSolutionPerStep);
  static_assert(kEventBudget >= 1 && kEventBudget <= kMaxEventsPerStep,
                "a law's declared event budget must be 1 to kMaxEventsPerStep");
  // Q7.24 runs in scene units only (models/scaled_oscillator.hpp), where m = 1 and dt = 1
  // exactly and the step is one tick (configure() requires them): its products by these are
  // exact and skipped (by_unit()), about 40 instructions each on the Cortex-M0+.
  static constexpr bool kSceneUnits = S::kSceneUnits;

  // Validates the parameters and precomputes every coefficient. The model in `params` must match
  // Law (checked); the oscillator is left reset to rest with a_u = 0.
  ConfigResult configure(const OscillatorParams& params) noexcept {
    DiscreteModel model;
    ConfigResult result = discretise(params, model);
    if (result.ok() && params.model != Law::model) {
      result = refusal(Status::unsupported);
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
                                         S::kEventTickLevel, parameter_units<S>());
      }
    }
    if constexpr (kSceneUnits) {
      // The cubic search's polynomials carry no powers of dt, and the step no products by m or
      // dt: in scene units (ScaledOscillator) both are 1.
      if (result.ok() && params.dt_s != 1.0) {
        result = refusal(Status::out_of_range);
        result.message
            .append("dt_s: this scalar runs in scene units, dt = 1 (ScaledOscillator); got ")
            .append(params.dt_s);
      } else if (result.ok() && params.mass_kg != 1.0) {
        result = refusal(Status::out_of_range);
        result.message
            .append("mass_kg: this scalar runs in scene units, m = 1 (ScaledOscillator); got ")
            .append(params.mass_kg);
      }
    }
    if constexpr (kSceneUnits) {
      // Q7.24 keeps to the seats its cubic search was verified over (a condition narrower than
      // omega0 dt <= pi/2: CubicSegmentRootIsExactToTheFormatsRounding draws seats within it).
      const double reach = model.damping_over_mass * params.dt_s +
                           0.5 * model.stiffness_over_mass * params.dt_s * params.dt_s;
      if (result.ok() && !(reach < 1.0)) {
        result = refusal(Status::out_of_range);
        result.message.append("dt_s: (b/m) dt + (k/m) dt^2/2 = ")
            .append(reach)
            .append(
                ", not below 1: beyond the seats Q7.24's cubic event search is verified "
                "for");
      }
    }
    if (!result.ok()) return result;
    for (int level = 0; level < kMapLevels; ++level) {
      maps_[level] = step_map_of<T>(model, params, level);
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
    friction_.stribeck_min_exponential = stribeck_min_exponential<T>(model.stribeck_excess_n);
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
    // (A fixed-point scalar bisects and interpolates in ticks of its own size, or with one tick
    // per step solves the cubic polynomial inside it: ScalarTraits::kCubicEventSearch.)
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
      counters_.saturated_steps = 0;
    }
    return result;
  }

  // Initial state x_r = x0, v_r = v0 with the input at a_u0. A sticking law starts stuck when
  // v0 = 0 and |F_L(0)| <= F_fs; otherwise it slips in the direction of v0 (or of F_L).
  void reset(T x0_m, T v0_m_per_s, T a_u0) noexcept { reset_shifted(x0_m, v0_m_per_s, a_u0, a_u0); }
  // With an actuator force f_a0 acting at the start (in F_L(0)); see current_with_force().
  void reset(T x0_m, T v0_m_per_s, T a_u0, T f_a0_n) noexcept {
    reset_shifted(x0_m, v0_m_per_s, a_u0, a_u0 - by_unit(inv_mass_, f_a0_n));
  }

 private:
  // a_u_shifted = a_u0 - f_a0/m decides the initial mode; the next step starts from a_u0.
  void reset_shifted(T x0_m, T v0_m_per_s, T a_u0, T a_u_shifted) noexcept {
    x_ = x0_m;
    v_ = v0_m_per_s;
    a_prev_ = a_u0;
    counters_ = SafetyCounters{};
    if constexpr (Law::kind == LawKind::held) {
      held_force_ = Law::force(v_, friction_);
      reported_force_ = held_force_;
    } else if constexpr (Law::kind == LawKind::sticking) {
      const T limit = limit_force(a_u_shifted, x_);
      if (v_ == T(0)) {
        direction_ = S::abs(limit) <= friction_.static_n ? T(0) : signum(limit);
      } else {
        direction_ = signum(v_);
      }
    }
    slip_a_x_ = current().a_x_m_per_s2;
  }

 public:
  // The outputs for the current state (the first row of a simulation, before any step).
  StepOutput<T> current() const noexcept { return output(a_prev_, T(0), 0); }
  // The same with the actuator force f_a acting on that state.
  StepOutput<T> current_with_force(T f_a_n) const noexcept {
    StepOutput<T> out = output(a_prev_ - by_unit(inv_mass_, f_a_n), T(0), 0);
    actuated_step_output(out, a_prev_, by_unit(inv_mass_, f_a_n));
    return out;
  }

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
    step_unchecked<false>(a_u_next, T(0), out);
    count_saturation();
  }

  // With the actuator force f_a_n (N) held over the step; a non-finite one counts as rejected and
  // acts as 0. Fixed point: input_range_m_per_s2 must cover |a_u - f_a/m|, the step's input.
  STICKSLIP_INLINE_STEP StepOutput<T> step(T a_u_next, T f_a_n) noexcept {
    StepOutput<T> out;
    step(a_u_next, f_a_n, out);
    return out;
  }
  STICKSLIP_INLINE_STEP void step(T a_u_next, T f_a_n, StepOutput<T>& out) noexcept {
    if (!S::is_finite(f_a_n)) {
      f_a_n = T(0);
      ++counters_.rejected_inputs;
    }
    step_unchecked<true>(a_u_next, by_unit(inv_mass_, f_a_n), out);
    count_saturation();
  }

 private:
  void count_saturation() noexcept {
    if constexpr (S::kTracksSaturation) {
      // Fixed point: every operation of this step that saturated set the sticky flag (so did
      // the caller's conversion of a_u_next, if it did not fit): count the step.
      if (S::take_saturation()) ++counters_.saturated_steps;
    }
  }

 private:
  // Every path fills `out` in place (no temporary copies of it: 28 bytes each on the M0+, whose
  // stack is the scarce resource).
  // kActuated: the input is a_u - accel_offset (= f_a/m); without it no offset is formed at all.
  template <bool kActuated>
  STICKSLIP_INLINE_STEP void step_unchecked(T a_u_next, T accel_offset,
                                            StepOutput<T>& out) noexcept {
    if (!S::is_finite(a_u_next)) {  // replaced by the previous sample, counted
      a_u_next = a_prev_;
      ++counters_.rejected_inputs;
    }
    Input in{a_prev_, a_u_next};
    if constexpr (kActuated) in = Input{a_prev_ - accel_offset, a_u_next - accel_offset};
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
        const T limit = limit_force(in.a1, x_);
        bool holds = !stuck_step_breaks_away(limit, friction_.static_n);
        if constexpr (kActuated)  // F_L jumps at the step's start if the force changed there
          holds = holds && !stuck_step_breaks_away(limit_force(in.a0, x_), friction_.static_n);
        if (holds) {
          a_prev_ = a_u_next;
          write_stuck_output(out, a_u_next, limit);
          return;
        }
        events = step_sticking(in, stuck_fraction, nullptr);
      } else if constexpr (!Law::velocity_dependent && S::kCompactStack) {
        if (whole_step_slips(in, out)) {
          a_prev_ = a_u_next;
          if constexpr (kActuated) actuated_step_output(out, a_u_next, accel_offset);
          return;
        }
        events = step_sticking(in, stuck_fraction, nullptr);
      } else if constexpr (!Law::velocity_dependent) {
        const T force = Law::slip_force(v_, direction_, friction_);
        const WholeSlip<T> moved =
            whole_step_slip(maps_[0], k_over_m_, b_over_m_, by_unit(inv_mass_, force), x_, v_,
                            slip_a_x_, in.a0, in.a1);
        if (!slip_step_has_event(moved, direction_)) {
          x_ = moved.x;
          v_ = moved.v;
          slip_a_x_ = moved.seat_acceleration;
          a_prev_ = a_u_next;
          write_slip_output(out, force, moved.seat_acceleration);
          if constexpr (kActuated) actuated_step_output(out, a_u_next, accel_offset);
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
    write_output(out, in.a1, stuck_fraction, events);
    slip_a_x_ = out.a_x_m_per_s2;  // the seat acceleration the next step starts from, if slipping
    if constexpr (kActuated) actuated_step_output(out, a_u_next, accel_offset);
  }

 public:
  T x_r() const noexcept { return x_; }
  T v_r() const noexcept { return v_; }
  bool stuck() const noexcept {
    if constexpr (Law::kind == LawKind::sticking) return direction_ == T(0);
    return false;
  }
  T dt_s() const noexcept { return dt_s_; }
  // The event search configure() chose: bisection to ticks of dt / 2^tick_level, then the Taylor
  // polynomial of that order (0: interpolation, or Q7.24's cubic over the whole step). The trip
  // counts of the step's block walk and root search follow from it (detail/event_search.hpp), so
  // a build that bounds its step's work checks it (port/baremetal/src/node.cpp).
  EventSearchPlan event_search() const noexcept { return {event_level_, taylor_.order}; }
  // Steps the event budget cut short (should stay 0; a non-zero count means a degenerate scene).
  std::uint64_t event_budget_exhausted() const noexcept { return counters_.event_budget_exhausted; }
  // The events one step locates at most, as configured: kEventBudget, or with RK4 and a friction
  // force that follows v_r inside a piece, kStageFrictionEventBudget.
  int event_budget() const noexcept {
    if constexpr (Law::velocity_dependent) {
      if (stage_friction_) return kStageFrictionEventBudget;
    }
    return kEventBudget;
  }
  // Non-finite input samples replaced by the previous sample.
  std::uint64_t rejected_inputs() const noexcept { return counters_.rejected_inputs; }
  // Times the non-finite guard restarted the state from rest (0 for any accepted configuration).
  std::uint64_t state_resets() const noexcept { return counters_.state_resets; }
  // Fixed point: steps in which an operation saturated (always 0 for float and double). Non-zero
  // means the scene left the ranges configure() checked (OscillatorParams::input_range_m_per_s2,
  // displacement_range_m): the outputs of those steps are clipped, not wrapped.
  std::uint64_t saturated_steps() const noexcept { return counters_.saturated_steps; }
  bool saturated() const noexcept { return counters_.saturated_steps != 0; }

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
    restore(s, slip_a_x_);
    slip_a_x_ = current().a_x_m_per_s2;
  }

 private:
  // The batch copies the coefficients of its lanes' common path (models/batch.hpp).
  template <typename, std::size_t>
  friend class StickSlipBatch;

  using Input = StepInput<T>;
  // Position inside the step: whole ticks of dt/2^event_level_ plus a fraction of the next tick.
  struct Position {
    unsigned tick;
    T frac;
  };
  // How a piece of slip motion begins: inside its slip phase, or at the phase's start from rest
  // (a break-away or a reversal), where v_r's rounding is clamped to the slip's direction; from
  // rest searched for a return to rest, or not where the exact solution has none in the step
  // (step_common.hpp).
  enum class PieceStart : unsigned char { kInPhase, kFromRest, kFromRestNoReturn };
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

  T phi(const Position& pos) const noexcept { return by_unit(inv_ticks_, T(pos.tick) + pos.frac); }

  // unit * value, for a unit that is 1 in scene units (m, 1/m, dt, 1/dt, the ticks per step):
  // there the product is the value itself (kSceneUnits).
  T by_unit(T unit, T value) const noexcept {
    if constexpr (kSceneUnits) return value;
    return unit * value;
  }

  // a_u at phi in the step; at its start (where most events of a step begin) without the
  // interpolation's two products in scene units.
  T input_at(const Input& in, T phi) const noexcept {
    if constexpr (kSceneUnits) {
      if (phi == T(0)) return in.a0;
    }
    return in.at(phi);
  }

  T limit_force(T a_u, T x) const noexcept { return -(by_unit(mass_kg_, a_u) + stiffness_ * x); }
  // The largest |F_L| a seat at rest counts as within F_fs: F_fs, and in floating point F_fs plus
  // 8 ulp of F_L's terms, its rounding. With |F_L| at F_fs to rounding (F_fk = F_fs and a floor
  // that holds it there) the exact motion is a slip too slow for the scalar to see; decided as a
  // reversal because F_L rounded beyond F_fs, each decision was an event without progress (float:
  // the whole event budget). Fixed point compares with F_fs itself.
  T holding_limit_n(T a_u, T x) const noexcept {
    if constexpr (S::kTaylorEventSearch) {
      return friction_.static_n +
             T(8) * S::epsilon() * (S::abs(mass_kg_ * a_u) + S::abs(stiffness_ * x));
    } else {
      return friction_.static_n;
    }
  }

  // dv_r/dt for a given friction force.
  T relative_acceleration(T x, T v, T force_n, T a_u) const noexcept {
    return seat_acceleration(k_over_m_, b_over_m_, x, v, by_unit(inv_mass_, force_n)) - a_u;
  }

  void advance_affine(T& x, T& v, int level, T g0, T g1) const noexcept {
    apply_step_map(maps_[level], x, v, g0, g1);
  }

  // The generalised input g = -(a_u + F_f/m) changes by this much per tick (first-order hold).
  T input_slope_per_tick(const Input& in) const noexcept { return -(in.a1 - in.a0) * inv_ticks_; }

  // The in-step event search and the rare paths of the step (models/detail/event_search.hpp).
  template <typename Force>
  void advance_rk4(T& x, T& v, int level, T a_u0, T a_u1, const Force& force) const noexcept;
  template <typename Force>
  void advance_block(T& x, T& v, unsigned tick, int level, const Input& in,
                     const Force& force) const noexcept;
  static int lowest_set_bit(unsigned value) noexcept;
  T rest_rounding_velocity(int level, T x, T force_n, T a_u_start, const Input& in) const noexcept;
  static void advance_within_tick(Position& pos, T fraction) noexcept;
  template <typename Segment>
  STICKSLIP_COMPACT_INLINE static bool end_on_segment(const Segment& segment, bool found, T root,
                                                      T u_start, Position& pos, T& x,
                                                      T& v) noexcept;
  STICKSLIP_COMPACT_INLINE bool finish_tick_taylor(Position& pos, T& x, T& v, T d, const Input& in,
                                                   T force_n, PieceStart start) const noexcept;
  STICKSLIP_COMPACT_INLINE bool finish_tick_cubic(Position& pos, T& x, T& v, T d, const Input& in,
                                                  T force_n, PieceStart start,
                                                  const T* a_u_at_pos) const noexcept;
  STICKSLIP_COMPACT_INLINE bool finish_tick_interpolated(Position& pos, T& x, T& v, T d,
                                                         const Input& in, T force_n,
                                                         PieceStart start) const noexcept;
  template <typename Force>
  STICKSLIP_COMPACT_INLINE bool slip(Position& pos, T& x, T& v, T d, const Input& in,
                                     const Force& force, PieceStart start = PieceStart::kInPhase,
                                     const WholeSlip<T>* whole_step = nullptr,
                                     const T* a_u_at_pos = nullptr) const noexcept;
  STICKSLIP_COMPACT_INLINE bool slip_piece(Position& pos, T d, const Input& in, PieceStart start,
                                           const WholeSlip<T>* whole_step,
                                           const T* a_u_at_pos) noexcept;
  STICKSLIP_OUT_OF_LINE int step_held(const Input& in) noexcept;
  STICKSLIP_OUT_OF_LINE bool whole_step_slips(const Input& in, StepOutput<T>& out) noexcept;
  STICKSLIP_OUT_OF_LINE int step_sticking(const Input& in, T& stuck_fraction,
                                          const WholeSlip<T>* whole_step) noexcept;

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
    out.stuck_time_s = by_unit(dt_s_, stuck_fraction);
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
    out.a_x_m_per_s2 = seat_acceleration(k_over_m_, b_over_m_, x_, v_, by_unit(inv_mass_, force));
  }

  // A running model never emits NaN/Inf: should the state ever leave the finite range (it cannot
  // for an accepted configuration and finite input), restart from rest and count it.
  void guard_state() noexcept {
    if (S::is_finite(x_) && S::is_finite(v_)) return;
    x_ = T(0);
    v_ = T(0);
    ++counters_.state_resets;
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
  using Map = StepMapOf<T>;  // double's near the identity (step_map.hpp)
  Map maps_[kMapLevels]{};
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

  // State. v_ before x_: with x_ first, GCC 12 (x86-64, -O2) stores the slipping step's x_, v_
  // as one 16-byte pair and reads v_ back in the next step with a 16-byte load that also covers
  // a_prev_, stored on its own; a load that straddles two stores cannot be forwarded from the
  // store buffer and waits for them to retire, which doubled the host's step time (6.5 to
  // 12.4 ns, docs/PERFORMANCE.md measures it).
  T v_{}, x_{}, a_prev_{};
  T held_force_{};      // held laws: friction at the start of the next step
  T reported_force_{};  // held laws: friction reported with the sample
  T direction_{};       // sticking laws: 0 stuck, +1/-1 slipping
  // Coulomb slip: a_x at the current state with the current slip force (what the previous step
  // reported), the start of the next step's dip test. Unused while stuck.
  T slip_a_x_{};
  SafetyCounters counters_{};
};

}  // namespace stickslip

#include "stickslip/models/detail/event_search.hpp"
