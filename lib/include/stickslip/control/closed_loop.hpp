// One sample of the closed loop, in process: plant -> sensors -> observer -> controller ->
// actuator, with the one-frame delay of an ECU's output stage. The force computed from the
// sensors of sample n is held over the next step (t_n to t_{n+1}), so step n+1 of the plant sees
// it: plant.step(a_u[n+1], f_a) with the f_a of sample n. Nothing here knows where the plant runs:
// the same step() drives an Oscillator in process, and a later CAN split calls the same code with
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
// Allocation-free; double and float (the state estimator offers no fixed point).
#pragma once

#include <cmath>

#include "stickslip/control/absolute_velocity.hpp"
#include "stickslip/control/actuator.hpp"
#include "stickslip/control/friction_compensation.hpp"
#include "stickslip/control/hook_damping.hpp"
#include "stickslip/control/sensor_sample.hpp"
#include "stickslip/control/user_controller.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/models/step_common.hpp"
#include "stickslip/observer/state_estimator.hpp"

namespace stickslip {

enum class LoopController : unsigned char { passive, hook, user };
enum class ObserverKind : unsigned char { estimator, ideal };

struct ClosedLoopParams {
  double dt_s = 1e-3;
  LoopController controller = LoopController::passive;
  HookParams hook;  // LoopController::hook
  // Feed-forward of the friction estimate (0: none), added to the controller's command.
  double friction_compensation_fraction = 0.0;
  ActuatorParams actuator;  // its dt_s is set from dt_s
  AbsoluteVelocityParams absolute_velocity;
  ObserverKind observer = ObserverKind::estimator;
  StateEstimatorParams estimator;  // its dt_s is set from dt_s
  // Sensor resolution (0: not quantised).
  double seat_acceleration_resolution_m_per_s2 = 0.0;
  double travel_resolution_m = 0.0;
};

// What the loop did at one sample.
template <typename T>
struct LoopSample {
  StepOutput<T> plant;  // the plant's step into this sample
  T applied_force_n;    // the force held over that step (computed at the previous sample)
  SensorSample<T> sensed;
  T command_n;     // the controller's command at this sample (before the actuator)
  T next_force_n;  // the actuator's force held over the next step
};

template <typename T>
class ClosedLoop {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const ClosedLoopParams& p) noexcept {
    if (!(p.dt_s > 0.0 && std::isfinite(p.dt_s))) {
      ConfigResult r = refusal(Status::out_of_range);
      r.message.append("dt_s: must be finite and > 0, got ").append(p.dt_s);
      return r;
    }
    const auto resolution_bad = [](const char* name, double value) {
      ConfigResult r = refusal(std::isfinite(value) ? Status::out_of_range : Status::not_finite);
      r.message.append(name).append(": must be finite and >= 0, got ").append(value);
      return r;
    };
    if (!(p.seat_acceleration_resolution_m_per_s2 >= 0.0 &&
          std::isfinite(p.seat_acceleration_resolution_m_per_s2)))
      return resolution_bad("seat_acceleration_resolution_m_per_s2",
                            p.seat_acceleration_resolution_m_per_s2);
    if (!(p.travel_resolution_m >= 0.0 && std::isfinite(p.travel_resolution_m)))
      return resolution_bad("travel_resolution_m", p.travel_resolution_m);
    ConfigResult r;
    if (p.controller == LoopController::hook) {
      r = hook_.configure(p.hook);
      if (!r.ok()) return r;
    }
    FrictionCompensationParams compensation;
    compensation.fraction = p.friction_compensation_fraction;
    r = compensation_.configure(compensation);
    if (!r.ok()) return r;
    ActuatorParams actuator = p.actuator;
    actuator.dt_s = p.dt_s;
    r = actuator_.configure(actuator);
    if (!r.ok()) return r;
    AbsoluteVelocityParams velocity = p.absolute_velocity;
    velocity.dt_s = p.dt_s;
    r = seat_velocity_.configure(velocity);
    if (!r.ok()) return r;
    floor_velocity_.configure(velocity);
    if (p.observer == ObserverKind::estimator) {
      StateEstimatorParams estimator = p.estimator;
      estimator.dt_s = p.dt_s;
      r = estimator_.configure(estimator);
      if (!r.ok()) return r;
      inverse_mass_ = S::from_double(1.0 / estimator.mass_kg);  // mass_kg > 0: checked above
    }
    controller_ = p.controller;
    observer_ = p.observer;
    compensate_ = p.friction_compensation_fraction > 0.0;
    a_x_quantum_ = S::from_double(p.seat_acceleration_resolution_m_per_s2);
    a_x_inverse_quantum_ = S::from_double(p.seat_acceleration_resolution_m_per_s2 > 0.0
                                              ? 1.0 / p.seat_acceleration_resolution_m_per_s2
                                              : 0.0);
    x_r_quantum_ = S::from_double(p.travel_resolution_m);
    x_r_inverse_quantum_ =
        S::from_double(p.travel_resolution_m > 0.0 ? 1.0 / p.travel_resolution_m : 0.0);
    return {};
  }

  // The user's controller (LoopController::user); without one the command is 0.
  void set_user_controller(const UserController<T>& user) noexcept { user_ = user; }

  // Start of a run: no force acting, the observer parked at x0 with the first floor sample, the
  // absolute velocities at rest.
  void reset(T a_u0, T x0_m = T(0)) noexcept {
    actuator_.reset(T(0));
    seat_velocity_.reset();
    floor_velocity_.reset();
    if (observer_ == ObserverKind::estimator) estimator_.reset(a_u0, x0_m);
  }

  // The force to hold over the next plant step (0 before the first sample).
  T force_n() const noexcept { return actuator_.force_n(); }

  // One sample: the plant steps to a_u under the held force, then the loop computes the next one.
  template <typename Plant>
  LoopSample<T> step(Plant& plant, T a_u, T a_x_noise_m_per_s2 = T(0),
                     T x_r_noise_m = T(0)) noexcept {
    LoopSample<T> sample;
    sample.applied_force_n = actuator_.force_n();
    sample.plant = plant.step(a_u, sample.applied_force_n);
    const T a_x_measured = quantise(sample.plant.a_x_m_per_s2 + a_x_noise_m_per_s2, a_x_quantum_,
                                    a_x_inverse_quantum_);
    const T x_r_measured =
        quantise(sample.plant.x_r_m + x_r_noise_m, x_r_quantum_, x_r_inverse_quantum_);
    T v_r = sample.plant.v_r_m_per_s, friction = sample.plant.friction_n;
    if (observer_ == ObserverKind::estimator) {
      // The estimator's model has no actuator input, but a force held over the step is a shift
      // of the input, a_u -> a_u - f/m (as in the core), and of the absolute acceleration the
      // model predicts, a_x -> a_x - f/m; the relative acceleration a_x - a_u is unchanged. Fed
      // so, the estimator's friction is the seat's F_f, not F_f - f_a (which would make a
      // friction feed-forward chase its own force). (The estimator holds its input first-order
      // between samples; the force steps at them: an approximation where the force changes.)
      const T shift = sample.applied_force_n * inverse_mass_;
      const StateEstimate<T>& estimate =
          estimator_.step(a_u - shift, a_x_measured - shift, x_r_measured);
      v_r = estimate.v_r_m_per_s;
      friction = estimate.friction_n;
    }
    sample.sensed = SensorSample<T>{a_u,
                                    a_x_measured,
                                    x_r_measured,
                                    v_r,
                                    seat_velocity_.step(a_x_measured),
                                    floor_velocity_.step(a_u),
                                    friction};
    T command = T(0);
    if (controller_ == LoopController::hook) command = hook_.step(sample.sensed);
    if (controller_ == LoopController::user) command = user_.step(sample.sensed);
    if (compensate_) command = command + compensation_.step(sample.sensed);
    sample.command_n = command;
    sample.next_force_n = actuator_.step(command);
    return sample;
  }

 private:
  static T quantise(T value, T quantum, T inverse_quantum) noexcept {
    if (!(quantum > T(0))) return value;
    return quantum * static_cast<T>(std::round(value * inverse_quantum));
  }

  LoopController controller_ = LoopController::passive;
  ObserverKind observer_ = ObserverKind::estimator;
  bool compensate_ = false;
  HookController<T> hook_;
  UserController<T> user_;
  FrictionCompensation<T> compensation_;
  Actuator<T> actuator_;
  AbsoluteVelocity<T> seat_velocity_, floor_velocity_;
  StateEstimator<T> estimator_;
  T a_x_quantum_{}, a_x_inverse_quantum_{}, x_r_quantum_{}, x_r_inverse_quantum_{};
  T inverse_mass_{};
};

}  // namespace stickslip
