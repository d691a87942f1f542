// One sample of the closed loop, in process: plant -> sensors -> observer -> controller ->
// actuator, with the one-frame delay of an ECU's output stage. The force computed from the
// sensors of sample n is held over the next step (t_n to t_{n+1}), so step n+1 of the plant sees
// it: plant.step(a_u[n+1], f_a) with the f_a of sample n. Nothing here knows where the plant runs:
// the same step() drives an Oscillator or an EndStopOscillator (any plant with step(a_u, f_a)
// returning a StepOutput) in process, and a later CAN split calls the same code with
// the plant on the other side of the bus.
//
// Per sample:
//   1. plant.step(a_u, f_held)                      (the exact core, models/oscillator.hpp)
//   2. sensors: a_x and x_r plus the caller's noise sample, quantised to the declared resolution
//      (round to nearest; 0 = no quantisation). The noise comes in as an argument because lib/
//      has no random source: the host draws it from a seeded generator, an ECU has real sensors.
//   3. observer: the state estimator (observer/state_estimator.hpp) corrected by the measured a_x
//      and x_r, and told the force that acted (as a shift of its input), gives v_r and the
//      friction estimate; with ObserverKind::ideal the controller reads
//      the plant's own v_r and F_f instead (perfect sensing: the bound of what an observer gives).
//   4. controller: passive (0), skyhook/groundhook, active or semi-active (hook_damping.hpp), or
//      the user's function (user_controller.hpp); plus an optional friction feed-forward
//      (friction_compensation.hpp) of the observer's friction estimate.
//   5. actuator: force limit and first-order lag (actuator.hpp); its output is the force held
//      over the next step.
// The absolute velocities the hook laws need come from the measured accelerations through leaky
// integrators (absolute_velocity.hpp), as an ECU without an absolute velocity sensor has them.
// Steps 3-5 are the ControlUnit (control_unit.hpp), the code an ECU on the far side of a bus
// runs. Allocation-free; double and float (the state estimator offers no fixed point).
#pragma once

#include <cmath>

#include "stickslip/control/control_unit.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip {

// What the loop did at one sample.
template <typename T>
struct LoopSample {
  StepOutput<T> plant;  // the plant's step into this sample
  T applied_force_n;    // the force held over that step (computed at the previous sample)
  SensorSample<T> sensed;
  T command_n;     // the controller's command at this sample (before the actuator)
  T next_force_n;  // the actuator's force held over the next step
};

// The plant's sensors: the true value plus the caller's noise, quantised to the declared
// resolution (0: not quantised).
template <typename T>
class LoopSensors {
 public:
  ConfigResult configure(const ClosedLoopParams& p) noexcept {
    ConfigResult r = a_x_.configure("seat_acceleration_resolution_m_per_s2",
                                    p.seat_acceleration_resolution_m_per_s2);
    if (!r.ok()) return r;
    return x_r_.configure("travel_resolution_m", p.travel_resolution_m);
  }
  T a_x(T value, T noise) const noexcept { return a_x_(value + noise); }
  T x_r(T value, T noise) const noexcept { return x_r_(value + noise); }

 private:
  Quantiser<T> a_x_, x_r_;
};

template <typename T>
class ClosedLoop {
 public:
  ConfigResult configure(const ClosedLoopParams& p) noexcept {
    if (!(p.dt_s > 0.0 && std::isfinite(p.dt_s))) {
      ConfigResult r = refusal(Status::out_of_range);
      r.message.append("dt_s: must be finite and > 0, got ").append(p.dt_s);
      return r;
    }
    ConfigResult r = sensors_.configure(p);
    if (!r.ok()) return r;
    return unit_.configure(p);
  }

  // The user's controller (LoopController::user); without one the command is 0.
  void set_user_controller(const UserController<T>& user) noexcept {
    unit_.set_user_controller(user);
  }

  // Start of a run: no force acting, the observer parked at x0 with the first floor sample, the
  // absolute velocities at rest.
  void reset(T a_u0, T x0_m = T(0)) noexcept { unit_.reset(a_u0, x0_m); }

  // The force to hold over the next plant step (0 before the first sample).
  T force_n() const noexcept { return unit_.force_n(); }

  // One sample: the plant steps to a_u under the held force, then the loop computes the next one.
  template <typename Plant>
  LoopSample<T> step(Plant& plant, T a_u, T a_x_noise_m_per_s2 = T(0),
                     T x_r_noise_m = T(0)) noexcept {
    LoopSample<T> sample;
    sample.applied_force_n = unit_.force_n();
    sample.plant = plant.step(a_u, sample.applied_force_n);
    const UnitSample<T> unit =
        unit_.step(a_u, sensors_.a_x(sample.plant.a_x_m_per_s2, a_x_noise_m_per_s2),
                   sensors_.x_r(sample.plant.x_r_m, x_r_noise_m), sample.applied_force_n,
                   sample.plant.v_r_m_per_s, sample.plant.friction_n);
    sample.sensed = unit.sensed;
    sample.command_n = unit.command_n;
    sample.next_force_n = unit.next_force_n;
    return sample;
  }

 private:
  LoopSensors<T> sensors_;
  ControlUnit<T> unit_;
};

}  // namespace stickslip
