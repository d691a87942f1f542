// The seat with end stops: the stroke is free within +-travel; beyond it a stiff, damped stop acts
// (Kelvin-Voigt: F_stop = k_s (x_r - travel sgn x_r) + b_s v_r while |x_r| > travel). Friction:
// none, Coulomb stick-slip (F_fs >= F_fk) or Gaussian Stribeck (the same stick logic; slipping,
// F_f = (F_fk + (F_fs - F_fk) exp(-(v_r/v_S)^2)) sgn v_r). Exact discretisation only. An actuator
// force f_a held over a step (step(a_u, f_a), as Oscillator's) is a shift of that step's input by
// -f_a/m.
//
// Between events the motion is linear in each mode (free or in contact, stuck or slipping one
// way), so it is advanced by that mode's precomputed exact affine maps (first-order-hold input),
// for the whole step or for dyadic blocks of it (dt / 2^l, l = 0..16), all computed in
// configure(). One event engine serves every mode boundary — contact and release (|x_r| =
// travel), stick and reversal (v_r = 0), break-away (|F_L| = F_fs): the maps scan the step's grid
// of 2^16 ticks (16 blocks, then bisection down to one tick), and inside that tick the boundary is
// solved for on the mode's Taylor polynomial (models/detail/end_stop_search.hpp); break-away,
// where F_L is linear in time, directly. In double the trajectory then agrees with the exact
// event-driven solution to rounding (tests/host/test_end_stop_exactness.cpp: a_x 2e-15..2e-14
// RMS in contact, the plain oscillator to 2e-15 with the stops out of reach). A contact or a
// double crossing of v_r = 0 shorter than a sixteenth of the step may go unseen; it moves the
// state by no more than that short interval can.
//
// Stribeck: the slip friction depends on v_r, so a slip phase has no closed form. As Oscillator's
// exact integrator does, the friction is held over each piece of motion at its value at the
// piece's start (the step's start, or the event that began the piece: break-away, reversal,
// contact, release) and the piece is then exact for that force: first order in dt (the figures
// and their refinement in tests/host/test_end_stop_stribeck.cpp). Out of reach of the stops the
// trajectory is the plain Oscillator<T, StribeckStickSlip>'s (exact integrator) to rounding.
//
// Fixed point (Q23.40; no friction or Coulomb): configure() checks the seat free and in contact
// for the format; inside a tick a second-order step and linear interpolation stand in for the
// Taylor polynomial (within_tick_interpolated), and saturated steps are counted. Q7.24 in scene
// units (ScaledEndStopOscillator, models/scaled_end_stops.hpp), where a tick of dt/2^16 would keep
// 8 significant bits: one tick per step, and inside it the mode's cubic polynomial of the exact
// solution (within_tick_cubic, ScalarTraits::kCubicEventSearch), as Oscillator's Q7.24 search.
//
// Common path (no event): one affine map and a few compares, like Oscillator's.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/integrators/cubic_segment.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/integrators/fixed_point_scaling.hpp"
#include "stickslip/integrators/step_map.hpp"
#include "stickslip/integrators/taylor_segment.hpp"
// Oscillator: the scene's seat without stops, which users of the stops compare against.
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip {

struct EndStopParams {
  double travel_m = 0.05;            // free stroke each way from x_r = 0
  double stiffness_n_per_m = 2.0e5;  // stop stiffness k_s (added to k while in contact)
  double damping_ns_per_m = 2.0e3;   // stop damping b_s (added to b while in contact)
};

// In contact the seat is a stiffer, more damped oscillator: k + k_s and b + b_s.
inline OscillatorParams contact_seat(const OscillatorParams& seat,
                                     const EndStopParams& stops) noexcept {
  OscillatorParams contact = seat;
  contact.stiffness_n_per_m += stops.stiffness_n_per_m;
  contact.damping_ns_per_m += stops.damping_ns_per_m;
  return contact;
}

// Validates the stop parameters (finite, travel > 0, k_s > 0, b_s >= 0) and, for the contact
// mode, what discretise() checks for k + k_s and b + b_s. Names the parameter.
ConfigResult check_end_stops(const OscillatorParams& seat, const EndStopParams& stops,
                             DiscreteModel& free_model, DiscreteModel& contact_model) noexcept;

// What the last step did at the stops (step() itself returns the StepOutput every model does).
template <typename T>
struct StopContacts {
  std::int8_t contact = 0;          // at the end of the step: -1 lower stop, 0 free, +1 upper stop
  std::uint8_t contact_events = 0;  // contacts begun inside this step
  T first_contact_s = T(-1);        // time into the step of the first contact begun, -1 if none
};

template <typename T, typename Law>
class EndStopOscillator {
  // (Or a law derived from one of them, as a test's that counts loop runs, step_common.hpp.)
  static_assert(std::is_base_of_v<NoFriction, Law> || std::is_base_of_v<CoulombStickSlip, Law> ||
                    std::is_base_of_v<StribeckStickSlip, Law>,
                "end stops are modelled with no friction, Coulomb stick-slip or Stribeck");
  using S = ScalarTraits<T>;
  static constexpr bool kSticking = Law::kind == LawKind::sticking;
  // Stribeck: the slip force is held per piece of motion (held_force_), not a constant.
  static constexpr bool kVelocityDependent = Law::velocity_dependent;
  // The event grid: 2^16 ticks per step, or in scene units (Q7.24) one tick per step with the
  // cubic polynomial of the exact solution inside it (ScalarTraits::kCubicEventSearch).
  static constexpr bool kCubic = S::kCubicEventSearch;
  static constexpr int kLevels = kCubic ? 0 : kEventLevels;
  static constexpr unsigned kTicks = 1u << kLevels;
  static constexpr unsigned kScanBlock = kTicks >= 16 ? kTicks / 16 : 1;  // the event scan's block

 public:
  using Scalar = T;
  using FrictionLaw = Law;
  // The most events the exact solution has in one step with a constant slip force
  // (step_common.hpp): 9 with Coulomb stick-slip, its 3 friction events and 6 contacts and
  // releases; 6 without friction.
  static constexpr int kExactSolutionEvents = kSticking
                                                  ? kMaxEndStopEventsOfTheExactSolutionPerStep
                                                  : kMaxStrokeEdgeEventsOfTheExactSolutionPerStep;
  // Events located in one step at most. At the budget the step finishes in its mode without a
  // search, and every step that reaches it before its end is counted in event_budget_exhausted().
  // With a constant slip force, one more than kExactSolutionEvents: a step that has them all
  // still searches the rest of the step, finds nothing and is not counted, so a count means a
  // located event the exact solution cannot have (rounding). Stribeck: the safety limit
  // kMaxEventsPerStep. A law may declare a smaller budget.
  static constexpr int kEventBudget = law_detail::event_budget<Law>(
      kVelocityDependent ? kMaxEventsPerStep : kExactSolutionEvents + 1);
  static_assert(kEventBudget >= 1 && kEventBudget <= kMaxEventsPerStep,
                "a law's declared event budget must be 1 to kMaxEventsPerStep");

  ConfigResult configure(const OscillatorParams& seat, const EndStopParams& stops) noexcept {
    DiscreteModel free_model, contact_model;
    ConfigResult result = check_end_stops(seat, stops, free_model, contact_model);
    if (!result.ok()) return result;
    if (seat.model != Law::model || seat.integrator != Integrator::exact) {
      result = refusal(Status::unsupported);
      const bool modelled = seat.model == FrictionModel::linear ||
                            seat.model == FrictionModel::stick_slip ||
                            seat.model == FrictionModel::stribeck;
      if (!modelled) {  // the laws the static_assert above admits
        result.message.append("end stops run the linear, stick-slip or stribeck model; got '")
            .append(model_name(seat.model))
            .append("'");
      } else if (seat.model != Law::model) {  // a model this class is not instantiated for
        result.message.append("this end-stop model runs the '")
            .append(model_name(Law::model))
            .append("' model; got '")
            .append(model_name(seat.model))
            .append("'");
      } else {
        result.message.append("end stops run the exact integrator; got '")
            .append(integrator_name(seat.integrator))
            .append("'");
      }
      return result;
    }
    if constexpr (S::kTracksSaturation) {
      // Fixed point: the edge of the stroke within the range the format keeps for displacements
      // (a travel it would saturate would silently move the stops).
      const double displacement_limit = std::ldexp(1.0, T::kIntegerBits - kFixedPointHeadroomBits);
      if (!(stops.travel_m <= displacement_limit)) {
        result = refusal(Status::out_of_range);
        result.message.append("end_stop_travel_m: travel = ")
            .append(stops.travel_m)
            .append(" is beyond what the format keeps (<= ")
            .append(displacement_limit)
            .append("); raise displacement_range_m to the travel");
        return result;
      }
      // Fixed point: the seat's coefficients and intermediates must fit the format, free and in
      // contact (the stiffer, more damped seat), down to the event grid's tick.
      // Q7.24 runs in scene units (ScaledEndStopOscillator).
      constexpr ParameterUnits units = parameter_units<S>();
      result = check_fixed_point_scene(seat, free_model, T::kIntegerBits, T::kFractionBits, kLevels,
                                       units);
      if (!result.ok()) return result;
      const ConfigResult in_contact =
          check_fixed_point_scene(contact_seat(seat, stops), contact_model, T::kIntegerBits,
                                  T::kFractionBits, kLevels, units);
      if (!in_contact.ok()) {
        result.status = in_contact.status;
        result.message
            .append(
                "in contact with an end stop (k + end_stop_stiffness_n_per_m, "
                "b + end_stop_damping_ns_per_m): ")
            .append(in_contact.message.c_str());
        return result;
      }
    }
    if constexpr (kCubic) {
      result = check_scene_units(seat, free_model, contact_model);
      if (!result.ok()) return result;
    }
    for (int l = 0; l <= kLevels; ++l) {
      maps_[0][l] = step_map_of<T>(free_model, seat, l);
      maps_[1][l] = step_map_of<T>(contact_model, contact_seat(seat, stops), l);
    }
    mass_kg_ = S::from_double(seat.mass_kg);
    inv_mass_ = S::from_double(free_model.inv_mass);
    stiffness_ = S::from_double(seat.stiffness_n_per_m);
    damping_ = S::from_double(seat.damping_ns_per_m);
    stop_stiffness_ = S::from_double(stops.stiffness_n_per_m);
    stop_damping_ = S::from_double(stops.damping_ns_per_m);
    travel_ = S::from_double(stops.travel_m);
    kinetic_n_ = S::from_double(kSticking ? seat.kinetic_friction_n : 0.0);
    static_n_ = S::from_double(kSticking ? seat.static_friction_n : 0.0);
    friction_.kinetic_n = kinetic_n_;
    friction_.static_n = static_n_;
    friction_.stribeck_excess_n = S::from_double(free_model.stribeck_excess_n);
    friction_.stribeck_min_exponential = stribeck_min_exponential<T>(free_model.stribeck_excess_n);
    friction_.inv_stribeck_velocity = S::from_double(free_model.inv_stribeck_velocity);
    dt_s_ = S::from_double(seat.dt_s);
    tick_fraction_ = S::from_double(1.0 / double(kTicks));  // a power of two
    // Inside a tick the exact motion of each mode is its Taylor polynomial, to an order whose
    // truncation is below the scalar's rounding.
    const double tick_s = seat.dt_s / double(kTicks), m = seat.mass_kg;
    tick_s_ = S::from_double(tick_s);
    const double stiff[2] = {seat.stiffness_n_per_m,
                             seat.stiffness_n_per_m + stops.stiffness_n_per_m};
    const double damp[2] = {seat.damping_ns_per_m, seat.damping_ns_per_m + stops.damping_ns_per_m};
    for (int mode = 0; mode < 2; ++mode) {
      stiffness_over_mass_[mode] = S::from_double(stiff[mode] / m);
      damping_over_mass_[mode] = S::from_double(damp[mode] / m);
      if constexpr (S::kTaylorEventSearch) {
        taylor_[mode].order = taylor_order(tick_s, stiff[mode] / m, damp[mode] / m);
        fill_taylor_coefficients(taylor_[mode], tick_s, stiff[mode] / m, damp[mode] / m);
      }
    }
    reset(T(0), T(0), T(0));
    if constexpr (S::kTracksSaturation) (void)S::take_saturation();  // the run starts clear
    return result;
  }

  void reset(T x0_m, T v0_m_per_s, T a_u0) noexcept { reset_shifted(x0_m, v0_m_per_s, a_u0, a_u0); }
  // With an actuator force f_a0 acting at the start (in F_L(0)); see current_with_force().
  void reset(T x0_m, T v0_m_per_s, T a_u0, T f_a0_n) noexcept {
    reset_shifted(x0_m, v0_m_per_s, a_u0, a_u0 - inv_mass_ * f_a0_n);
  }

  // Advances one sample: from the previous input a_u[n-1] to a_u_next = a_u[n].
  StepOutput<T> step(T a_u_next) noexcept {
    const StepOutput<T> out = step_unchecked<false>(a_u_next, T(0));
    count_saturation();
    return out;
  }
  // With the actuator force f_a_n (N, on the seat, upward positive) held over the step: the
  // step's input becomes a_u - f_a/m (every mode's map unchanged, exact stays exact), F_L = f_a -
  // (m a_u + k x_r + F_stop), and the outputs are those of a_u with f_a (actuated_step_output).
  // A non-finite force counts as rejected and acts as 0.
  StepOutput<T> step(T a_u_next, T f_a_n) noexcept {
    if (!S::is_finite(f_a_n)) {
      f_a_n = T(0);
      ++counters_.rejected_inputs;
    }
    const StepOutput<T> out = step_unchecked<true>(a_u_next, inv_mass_ * f_a_n);
    count_saturation();
    return out;
  }

 private:
  void count_saturation() noexcept {
    if constexpr (S::kTracksSaturation) {
      // Fixed point: every operation of this step that saturated set the sticky flag.
      if (S::take_saturation()) ++counters_.saturated_steps;
    }
  }

  // a_u_shifted = a_u0 - f_a0/m decides the initial mode; the next step starts from a_u0.
  void reset_shifted(T x0_m, T v0_m_per_s, T a_u0, T a_u_shifted) noexcept {
    x_ = x0_m;
    v_ = v0_m_per_s;
    a_prev_ = a_u0;
    contact_ = region(x_);
    direction_ = T(0);
    if constexpr (kSticking) {
      if (v_ != T(0)) {
        direction_ = v_ > T(0) ? T(1) : T(-1);
      } else if (S::abs(limit_force(x_, a_u_shifted)) > static_n_) {
        direction_ = limit_force(x_, a_u_shifted) > T(0) ? T(-1) : T(1);
      }
    } else {
      direction_ = T(1);  // no friction: "slipping" with zero force, never stuck
    }
    contacts_ = 0;
    counters_ = SafetyCounters{};
    refresh_force();
    acceleration_ = stuck() ? T(0) : seat_acceleration(x_, v_) - a_u_shifted;
  }

  // kActuated: the input is a_u - accel_offset (= f_a/m); without it no offset is formed at all
  // and the step is the passive one, instruction for instruction.
  template <bool kActuated>
  StepOutput<T> step_unchecked(T a_u_next, T accel_offset) noexcept {
    if (!S::is_finite(a_u_next)) {  // replaced by the previous sample, counted
      a_u_next = a_prev_;
      ++counters_.rejected_inputs;
    }
    Input in{a_prev_, a_u_next};
    if constexpr (kActuated) in = Input{a_prev_ - accel_offset, a_u_next - accel_offset};
    StopContacts<T>& out = contacts_last_;
    out = StopContacts<T>{};
    T stuck_fraction = T(0);
    int events = 0;

    if (kSticking && direction_ == T(0)) {
      // Stuck: F_L is linear in time over the step; it held at the start (unless a change of
      // the actuator force made it jump there).
      bool holds = S::abs(limit_force(x_, in.a1)) <= static_n_;
      if constexpr (kActuated) holds = holds && S::abs(limit_force(x_, in.a0)) <= static_n_;
      if (holds) {
        a_prev_ = a_u_next;
        out.contact = static_cast<std::int8_t>(contact_);
        StepOutput<T> result = output(in.a1, T(1), 0);
        if constexpr (kActuated) actuated_step_output(result, a_u_next, accel_offset);
        return result;
      }
    } else {
      // Slipping (or free): the whole step in the current mode, if nothing happens inside it.
      const ModeFrame frame = frame_of(contact_, x_, slip_force());
      T x = frame.local(x_), v = v_;
      apply_step_map(maps_[contact_ != 0 ? 1 : 0][0], x, v, -(in.a0 + frame.offset),
                     -(in.a1 + frame.offset));
      x = frame.x_r(x);
      const T a_x = seat_acceleration(x, v);
      // v_r' = a_x - a_u: the relative acceleration at both ends, the start's kept from before
      // (with a force, formed again: a change of f_a makes v_r' jump at the step's start).
      T acc0 = acceleration_;
      if constexpr (kActuated) acc0 = seat_acceleration(x_, v_) - in.a0;
      if (!event_between(x_, v_, acc0, x, v, a_x - in.a1)) {
        x_ = x;
        v_ = v;
        a_prev_ = a_u_next;
        out.contact = static_cast<std::int8_t>(contact_);
        if constexpr (kVelocityDependent) {
          // The next piece's force, from the state the step ended in (what the sample reports).
          refresh_force();
          const T a_x_end = seat_acceleration(x_, v_);
          acceleration_ = a_x_end - in.a1;
          if constexpr (kActuated) return slip_output(a_x_end + accel_offset);
          return slip_output(a_x_end);
        }
        acceleration_ = a_x - in.a1;
        if constexpr (kActuated) return slip_output(a_x + accel_offset);
        return slip_output(a_x);
      }
    }
    events = search(in, stuck_fraction, out);
    guard_state();
    refresh_force();
    a_prev_ = a_u_next;
    out.contact = static_cast<std::int8_t>(contact_);
    StepOutput<T> result = output(in.a1, stuck_fraction, events);
    acceleration_ = result.stuck ? T(0) : result.a_x_m_per_s2 - in.a1;
    if constexpr (kActuated) actuated_step_output(result, a_u_next, accel_offset);
    return result;
  }

 public:
  T x_r() const noexcept { return x_; }
  T v_r() const noexcept { return v_; }
  int contact() const noexcept { return contact_; }
  // The stop's force on the seat at the current state (0 in the free stroke), N.
  T stop_force_n() const noexcept {
    return contact_ == 0 ? T(0)
                         : stop_stiffness_ * (x_ - travel_ * T(contact_)) + stop_damping_ * v_;
  }
  const StopContacts<T>& last_step_contacts() const noexcept { return contacts_last_; }
  bool stuck() const noexcept { return kSticking && direction_ == T(0); }
  std::uint64_t contacts() const noexcept { return contacts_; }
  // The event search: ticks of dt / 2^kLevels (compile-time: 16, or one tick per step in Q7.24),
  // inside a tick the Taylor polynomial of the larger order of the free and the contact mode (0
  // where the scalar solves no Taylor polynomial). The trip counts of its coefficient and Horner
  // loops follow from the order, so a build that bounds its step's work checks it
  // (port/baremetal/src/node.cpp).
  EventSearchPlan event_search() const noexcept {
    return {kLevels, taylor_[0].order > taylor_[1].order ? taylor_[0].order : taylor_[1].order};
  }
  std::uint64_t event_budget_exhausted() const noexcept { return counters_.event_budget_exhausted; }
  std::uint64_t rejected_inputs() const noexcept { return counters_.rejected_inputs; }
  std::uint64_t state_resets() const noexcept { return counters_.state_resets; }
  // Fixed point: steps in which an operation saturated (always 0 for float and double); see
  // Oscillator::saturated_steps().
  std::uint64_t saturated_steps() const noexcept { return counters_.saturated_steps; }
  bool saturated() const noexcept { return counters_.saturated_steps != 0; }
  // The output at the current state with the last input (row 0 of a run, as Oscillator's).
  StepOutput<T> current() const noexcept { return output(a_prev_, stuck() ? T(1) : T(0), 0); }
  // The same with the actuator force f_a acting on that state.
  StepOutput<T> current_with_force(T f_a_n) const noexcept {
    const T offset = inv_mass_ * f_a_n;
    StepOutput<T> out = output(a_prev_ - offset, stuck() ? T(1) : T(0), 0);
    actuated_step_output(out, a_prev_, offset);
    return out;
  }
  // Mechanical energy of the seat: kinetic, spring and stop (J).
  double energy_j() const noexcept {
    const double x = S::to_double(x_), v = S::to_double(v_);
    const double m = S::to_double(mass_kg_), k = S::to_double(stiffness_);
    const double pen = penetration(x);
    return 0.5 * m * v * v + 0.5 * k * x * x + 0.5 * S::to_double(stop_stiffness_) * pen * pen;
  }

 private:
  using Input = StepInput<T>;

  int region(T x) const noexcept { return x > travel_ ? 1 : (x < -travel_ ? -1 : 0); }
  double penetration(double x) const noexcept {
    const double travel = S::to_double(travel_);
    return x > travel ? x - travel : (x < -travel ? x + travel : 0.0);
  }
  // Spring force of the stop in the current mode at x (its damping vanishes with v_r = 0).
  T stop_spring_force(T x) const noexcept {
    return contact_ == 0 ? T(0) : stop_stiffness_ * (x - travel_ * T(contact_));
  }
  // In contact fixed point's maps form the stop's spring force as k_s x - k_s travel, two terms
  // each far larger than their difference: their magnitudes, not the force, set the rounding the
  // rules below count. Floating point's maps act on the penetration (frame_of()), whose
  // rounding these magnitudes bound too.
  T stop_map_terms(T x) const noexcept {
    return contact_ == 0 ? T(0) : stop_stiffness_ * (S::abs(x) + travel_);
  }
  // The largest |F_L| the seat at rest counts as within F_fs: F_fs, and in floating point F_fs
  // plus 8 ulp of F_L's terms, its rounding. At rest with |F_L| at F_fs to rounding (F_fk = F_fs
  // and a floor that holds it there) the exact motion is a slip too slow for the scalar to see;
  // a slip that rounding ends at once, decided again as a slip or a break-away because F_L
  // rounded beyond F_fs, would spend an event per decision without progress (float: the whole
  // event budget). The seat stays at rest instead, and breaks away once |F_L| rises beyond
  // F_fs. Q7.24 (the cubic search) compares with F_fs itself.
  T holding_limit_n(T x, T a_u) const noexcept {
    if constexpr (kCubic) {
      (void)x, (void)a_u;
      return static_n_;
    } else {
      return static_n_ + T(8) * S::epsilon() *
                             (S::abs(mass_kg_ * a_u) + S::abs(stiffness_ * x) + stop_map_terms(x));
    }
  }
  // Lowest Taylor order (>= 2) whose remainder over one tick, (rate H)^(K+1)/(K+1)!, is below a
  // sixteenth of the scalar's epsilon; rate = omega0 + b/m bounds the growth of every derivative.
  static int taylor_order(double tick_s, double stiffness_over_mass,
                          double damping_over_mass) noexcept {
    const double rate = (std::sqrt(stiffness_over_mass) + damping_over_mass) * tick_s;
    const double target = S::to_double(S::epsilon()) / 16.0;
    double term = rate;
    for (int order = 1; order < kMaxTaylorOrder; ++order) {
      term *= rate / double(order + 1);
      if (order >= 2 && term <= target) return order;
    }
    return kMaxTaylorOrder;
  }
  // Scene units (Q7.24): the cubic polynomial takes the step as its unit of time and the seat's
  // mass as its unit of mass (ScaledEndStopOscillator converts), and is verified, as
  // Oscillator's, for seats with (b/m) dt + (k/m) dt^2/2 < 1: here free and in contact.
  static ConfigResult check_scene_units(const OscillatorParams& seat,
                                        const DiscreteModel& free_model,
                                        const DiscreteModel& contact_model) noexcept {
    ConfigResult result;
    if (seat.dt_s != 1.0 || seat.mass_kg != 1.0) {
      result = refusal(Status::out_of_range);
      result.message.append(seat.dt_s != 1.0 ? "dt_s" : "mass_kg")
          .append(": this scalar runs in scene units, dt = 1 and m = 1 (ScaledEndStopOscillator)");
      return result;
    }
    const DiscreteModel* models[2] = {&free_model, &contact_model};
    for (int mode = 0; mode < 2; ++mode) {
      const double reach =
          models[mode]->damping_over_mass + 0.5 * models[mode]->stiffness_over_mass;
      if (!(reach < 1.0)) {
        result = refusal(Status::out_of_range);
        // In contact, named by the stop's larger term.
        const bool damped =
            models[mode]->damping_over_mass >= 0.5 * models[mode]->stiffness_over_mass;
        result.message
            .append(mode == 0
                        ? "dt_s"
                        : (damped ? "end_stop_damping_ns_per_m" : "end_stop_stiffness_n_per_m"))
            .append(mode == 0 ? ": " : ": in contact, ")
            .append("(b/m) dt + (k/m) dt^2/2 = ")
            .append(reach)
            .append(", not below 1: beyond the seats Q7.24's cubic event search is verified for");
        return result;
      }
    }
    return result;
  }
  // F_L = m a_u + k x_r + F_stop(x_r): the force friction must hold for the seat to stay put.
  T limit_force(T x, T a_u) const noexcept {
    return mass_kg_ * a_u + stiffness_ * x + stop_spring_force(x);
  }

  // In floating point the maps of a mode act on x_r measured from its anchor, c travel: 0 in the
  // free stroke, the stop's edge in contact, where (p = x_r - c travel)
  //   m p'' = -(k + k_s) p - (b + b_s) v_r - (F_f + k c travel) - m a_u.
  // On x_r itself the contact maps form x_r' from terms the size of the travel that cancel to the
  // size of the penetration, and round it each step by eps travel, where the stop's energy moves
  // with the penetration: an undamped seat's energy drifted by about 5e-15 with every step in
  // contact on stops of 1e8 N/m (omega dt = 2.1 there). The anchor is taken while |x_r| is within
  // twice the travel, where it is subtracted exactly; deeper in a stop the penetration is at least
  // the travel, the terms no longer cancel, and rounding x_r - c travel in every advance() would
  // itself move the energy at each of the scan's calls (Coulomb at 0 N, 0.15 m into stops of
  // 3e7 N/m: 1e-9 in 1e6 steps): there the maps act on x_r. Fixed point rounds a product to an
  // absolute unit whatever the size of its terms: there the maps act on x_r itself, and the
  // firmware's Q7.24 step is the same.
  static constexpr bool kAnchored = !S::kTracksSaturation;
  // Each mode's maps, as the plain seat's: double's near the identity (StepMapOf, step_map.hpp),
  // so that out of reach of the stops a step without events is the plain seat's bit for bit.
  using Map = StepMapOf<T>;
  // A mode's frame as its maps take it: x_r from the anchor, and the mode's constant forces over m
  // (the maps' input is g = -(a_u + offset)).
  struct ModeFrame {
    T anchor;
    T offset;
    T local(T x_r) const noexcept {
      if constexpr (kAnchored) {
        return x_r - anchor;
      } else {
        return x_r;
      }
    }
    T x_r(T local) const noexcept {
      if constexpr (kAnchored) {
        return anchor + local;
      } else {
        return local;
      }
    }
  };
  ModeFrame frame_of(int c, T x, T force_n) const noexcept {
    if constexpr (kAnchored) {
      if (c != 0 && S::abs(x) <= T(2) * travel_) {
        const T anchor = travel_ * T(c);
        return {anchor, inv_mass_ * (force_n + stiffness_ * anchor)};
      }
    } else {
      (void)x;
    }
    return {T(0), inv_mass_ * (force_n - stop_stiffness_ * travel_ * T(c))};
  }

  // Advances (x, v) from tick `from` by `count` ticks in mode (contact c, friction force_n held),
  // as dyadic blocks (largest first): exact for the mode's linear motion with the FOH input.
  void advance(T& x, T& v, int c, T force_n, unsigned from, unsigned count,
               const Input& in) const noexcept {
    const ModeFrame frame = frame_of(c, x, force_n);
    const T offset = frame.offset;
    const Map* maps = maps_[c != 0 ? 1 : 0];
    T p = frame.local(x);
    unsigned at = from;
    for (int level = 0; level <= kLevels && count > 0; ++level) {
      const unsigned block = kTicks >> level;
      while (count >= block) {
        apply_step_map(maps[level], p, v, -(in.at(T(at) * tick_fraction_) + offset),
                       -(in.at(T(at + block) * tick_fraction_) + offset));
        at += block;
        count -= block;
      }
    }
    x = frame.x_r(p);
  }

  // The seat's absolute acceleration at (x, v) while slipping in the current direction (or free):
  // -(k x + b v + F_stop + F_f) / m.
  T seat_acceleration(T x, T v) const noexcept {
    const int c = contact_;
    const T stop = c == 0 ? T(0) : stop_stiffness_ * (x - travel_ * T(c)) + stop_damping_ * v;
    return -(inv_mass_ * (stiffness_ * x + damping_ * v + stop + slip_force()));
  }
  // The friction force of the current piece of motion while slipping: F_fk d (Coulomb), or the
  // Stribeck force held from the piece's start (refresh_force()); 0 for the frictionless seat.
  T slip_force() const noexcept {
    if constexpr (kVelocityDependent) {
      return held_force_;
    } else {
      return kinetic_n_ * direction_;
    }
  }
  // Stribeck: a piece of motion starts at the current state; its force is the law's there.
  void refresh_force() noexcept {
    if constexpr (kVelocityDependent) {
      held_force_ = direction_ == T(0) ? T(0) : Law::slip_force(v_, direction_, friction_);
    }
  }
  StepOutput<T> slip_output(T a_x) const noexcept {
    StepOutput<T> o{};
    o.x_r_m = x_;
    o.v_r_m_per_s = v_;
    o.a_x_m_per_s2 = a_x;
    o.friction_n = slip_force();
    o.stuck_time_s = T(0);
    o.stuck_fraction = T(0);
    o.stuck = false;
    o.events = 0;
    return o;
  }

  // Whether a step from (x0, v0) to (x1, v1) in the current mode may contain an event: a region
  // change, v_r reaching 0 against the slip direction, or v_r dipping towards 0 and back (a
  // possible double crossing, for which the search scans the step), and for the frictionless seat
  // a turn of v_r (its x_r may have touched a stop in between).
  bool event_between(T x0, T v0, T acc0, T x1, T v1, T acc1) const noexcept {
    if (mode_ends(x1, v1)) return true;
    const T d = direction_;
    if constexpr (kSticking) {
      if (v1 * d <= T(0)) return true;
      return (acc0 * d < T(0)) && (acc1 * d > T(0));
    } else {
      // A turn of v_r matters only where the turning point could reach a stop: it lies within
      // max|v_r| dt of the ends.
      const bool turns = (v0 * v1 <= T(0)) || ((v0 * acc0 < T(0)) && (v1 * acc1 > T(0)));
      const T reach = (S::abs(x0) > S::abs(x1) ? S::abs(x0) : S::abs(x1)) +
                      (S::abs(v0) > S::abs(v1) ? S::abs(v0) : S::abs(v1)) * dt_s_;
      return turns && (contact_ != 0 || reach > travel_);
    }
  }

  // True when, at state (x, v), the current mode no longer holds.
  bool mode_ends(T x, T v) const noexcept {
    if (stroke_ends(x)) return true;
    if constexpr (kSticking) return v * direction_ <= T(0);
    return false;
  }
  bool stroke_ends(T x) const noexcept {
    return contact_ == 0 ? region(x) != 0 : x * T(contact_) < travel_;
  }
  // The rounding of v_r over `count` ticks from tick `at` started near rest: 8 ulp of the
  // velocity change each acceleration term alone would make over them (spring, stop, friction,
  // input). A slip that starts at rest with the seat balanced at the break-away limit (a_r ~ 0,
  // F_fk = F_fs) ends a block with a v_r of either sign by rounding alone; taken as a stick, the
  // seat would break away again at once (|F_L| is F_fs to rounding) and spend an event per tick
  // with no progress (float: the whole event budget in such a step). A v_r at or against the
  // slip's direction within this rounding, at the end of a block that started within it, is no
  // event: it is 0 (Oscillator::rest_rounding_velocity(), the plain seat's rule). A
  // genuine stick still shows once a_r exceeds the rounding of its terms.
  T rest_rounding_velocity(T x, unsigned at, unsigned count, const Input& in) const noexcept {
    const T terms =
        inv_mass_ * (S::abs(stiffness_ * x) + stop_map_terms(x) + S::abs(slip_force())) +
        S::abs(in.at(T(at) * tick_fraction_)) + S::abs(in.a0) + S::abs(in.a1);
    return T(8) * S::epsilon() * T(count) * tick_s_ * terms;
  }

  // A place inside the step: whole ticks plus a fraction of the next one (so that the step's end
  // is reached exactly), and the step fraction phi it stands for.
  struct Position {
    unsigned tick;
    T frac;
  };
  T phi(const Position& pos) const noexcept { return (T(pos.tick) + pos.frac) * tick_fraction_; }
  // What ended a mode inside a tick.
  enum class Boundary : std::uint8_t { none, velocity, stroke };

  // The in-step event search (models/detail/end_stop_search.hpp).
  int search(const Input& in, T& stuck_fraction, StopContacts<T>& out) noexcept;
  bool break_away(const Input& in, Position& pos, T& stuck_fraction) noexcept;
  Boundary move_to_mode_end(const Input& in, Position& pos, bool detect) noexcept;
  Boundary leave_at_tick(const Input& in, unsigned lo, T x, T v, T xn, T vn,
                         Position& pos) noexcept;
  bool dips(const Input& in, T x, T v, unsigned at, unsigned next, T a_start,
            T a_end) const noexcept;
  // a_r d at (x, v) and tick `at` in the current slip: negative where |v_r| falls.
  T acceleration_along_slip(T x, T v, unsigned at, const Input& in) const noexcept {
    return (seat_acceleration(x, v) - in.at(T(at) * tick_fraction_)) * direction_;
  }
  Boundary within_tick(const Input& in, Position& pos, T& x, T& v, bool detect) const noexcept;
  Boundary within_tick_taylor(const Input& in, Position& pos, T& x, T& v,
                              bool detect) const noexcept;
  Boundary within_tick_interpolated(const Input& in, Position& pos, T& x, T& v,
                                    bool detect) const noexcept;
  Boundary within_tick_cubic(const Input& in, Position& pos, T& x, T& v,
                             bool detect) const noexcept;
  template <typename Segment>
  static Boundary end_on_segment(const Segment& segment, Boundary found, T end, Position& pos, T& x,
                                 T& v) noexcept;
  bool span_leaves_mode(const Input& in, T x, T v, unsigned at, unsigned count, T& xn, T& vn,
                        bool rest_rule) const noexcept;
  unsigned first_tick_leaving_mode(const Input& in, unsigned lo, unsigned hi, T& x, T& v, T& x_hi,
                                   T& v_hi) const noexcept;
  void enter_mode_at(const Input& in, const Position& pos, Boundary boundary,
                     StopContacts<T>& out) noexcept;
  // Whether the motion of a tick from x to x_end leaves the mode through the stroke (the first
  // boundary before x_end): the edge, and f(u) = s (x(u) - edge), which is <= 0 in the mode and
  // > 0 out, at both ends.
  struct StrokeCrossing {
    bool leaves;
    T edge, s, f_lo, f_hi;
  };
  StrokeCrossing stroke_crossing(T x, T x_end) const noexcept {
    StrokeCrossing c{};
    c.leaves = contact_ == 0 ? region(x_end) != 0 : x_end * T(contact_) < travel_;
    if (!c.leaves) return c;
    c.edge = boundary_ahead(x_end);
    c.s = contact_ != 0 ? T(-contact_) : (c.edge > T(0) ? T(1) : T(-1));
    c.f_lo = c.s * (x - c.edge);
    c.f_hi = c.s * (x_end - c.edge);
    return c;
  }
  // The stroke boundary the current mode can leave through towards (x, v): the stop ahead in
  // the free stroke, the stop's edge in contact.
  T boundary_ahead(T x) const noexcept {
    if (contact_ != 0) return travel_ * T(contact_);
    return x > T(0) ? travel_ : -travel_;
  }

  // A running model never emits NaN/Inf: a non-finite state (never for an accepted scene)
  // restarts from rest, counted.
  void guard_state() noexcept {
    if (S::is_finite(x_) && S::is_finite(v_)) return;
    x_ = v_ = T(0);
    direction_ = kSticking ? T(0) : T(1);
    contact_ = 0;
    refresh_force();
    ++counters_.state_resets;
  }

  StepOutput<T> output(T a_u, T stuck_fraction, int events) const noexcept {
    StepOutput<T> o{};
    o.x_r_m = x_;
    o.v_r_m_per_s = v_;
    const int c = contact_;
    const T stop = c == 0 ? T(0) : stop_stiffness_ * (x_ - travel_ * T(c)) + stop_damping_ * v_;
    if (kSticking && direction_ == T(0)) {
      o.friction_n = -limit_force(x_, a_u);  // holding force
      o.a_x_m_per_s2 = a_u;                  // stuck: the seat moves with the floor, exactly
      o.stuck = true;
    } else {
      o.friction_n = slip_force();
      o.a_x_m_per_s2 = -inv_mass_ * (stiffness_ * x_ + damping_ * v_ + stop + o.friction_n);
      o.stuck = false;
    }
    o.stuck_fraction = stuck_fraction;
    o.stuck_time_s = stuck_fraction * dt_s_;
    o.events = static_cast<std::uint8_t>(events);
    return o;
  }

  Map maps_[2][kLevels + 1]{};         // [free, contact][level]
  TaylorCoefficients<T> taylor_[2]{};  // [free, contact], one tick
  T mass_kg_{}, inv_mass_{}, stiffness_{}, damping_{};
  T stop_stiffness_{}, stop_damping_{}, travel_{};
  T kinetic_n_{}, static_n_{};
  FrictionCoefficients<T> friction_{};  // Stribeck: the law's coefficients
  T dt_s_{}, tick_fraction_{}, tick_s_{};
  T stiffness_over_mass_[2]{}, damping_over_mass_[2]{};  // [free, contact]: (k + k_s c)/m, ...
  T x_{}, v_{}, a_prev_{}, direction_{};
  T acceleration_{};  // v_r' at the current state (0 while stuck)
  T held_force_{};    // Stribeck: the friction held over the current piece of motion
  int contact_ = 0;
  StopContacts<T> contacts_last_{};
  std::uint64_t contacts_ = 0;
  SafetyCounters counters_{};
};

}  // namespace stickslip

#include "stickslip/models/detail/end_stop_search.hpp"
