// The ECU half of the closed loop: observer -> controller -> actuator, fed by the measured
// sensors of one sample, returning the force to hold over the next step. ClosedLoop
// (closed_loop.hpp) puts it behind an in-process plant; the `stickslip controller` node runs the
// same object on the far side of a CAN bus, so the two are the same code to the bit.
//
// The bus's view: a_u reaches the unit quantised to its frame's resolution, and the force leaves
// it quantised to the command frame's (power-of-two quanta, so quantise() here equals the CAN
// codec's round trip exactly). Resolution 0: not quantised (the in-process default).
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
  // The bus between plant and ECU (0: none): a_u as the ECU receives it, and the force as the
  // command frame carries it.
  double floor_acceleration_resolution_m_per_s2 = 0.0;
  double force_resolution_n = 0.0;
};

// A declared resolution (>= 0 and finite; 0: not quantised) and the rounding to it.
template <typename T>
class Quantiser {
  using S = ScalarTraits<T>;

 public:
  // `name` is the parameter the refusal names.
  ConfigResult configure(const char* name, double resolution) noexcept {
    if (!(resolution >= 0.0 && std::isfinite(resolution))) {
      ConfigResult r =
          refusal(std::isfinite(resolution) ? Status::out_of_range : Status::not_finite);
      r.message.append(name).append(": must be finite and >= 0, got ").append(resolution);
      return r;
    }
    quantum_ = S::from_double(resolution);
    inverse_quantum_ = S::from_double(resolution > 0.0 ? 1.0 / resolution : 0.0);
    return {};
  }
  // The nearest multiple of the quantum (halves away from zero, as std::round and the CAN
  // codec); quantum 0: the value itself. A value that rounds to zero is +0, as the codec's
  // integer code decodes (+ 0 turns -0 into +0 and leaves every other value as it is).
  T operator()(T value) const noexcept {
    if (!(quantum_ > T(0))) return value;
    return quantum_ * static_cast<T>(std::round(value * inverse_quantum_)) + T(0);
  }

 private:
  T quantum_{}, inverse_quantum_{};
};

// What the unit did at one sample.
template <typename T>
struct UnitSample {
  SensorSample<T> sensed;
  T command_n;     // the controller's command (before the actuator)
  T next_force_n;  // the actuator's force held over the next step (quantised to the bus)
};

template <typename T>
class ControlUnit {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const ClosedLoopParams& p) noexcept {
    if (!(p.dt_s > 0.0 && std::isfinite(p.dt_s))) {
      ConfigResult r = refusal(Status::out_of_range);
      r.message.append("dt_s: must be finite and > 0, got ").append(p.dt_s);
      return r;
    }
    ConfigResult r = a_u_seen_.configure("floor_acceleration_resolution_m_per_s2",
                                         p.floor_acceleration_resolution_m_per_s2);
    if (!r.ok()) return r;
    r = force_sent_.configure("force_resolution_n", p.force_resolution_n);
    if (!r.ok()) return r;
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
    return {};
  }

  // The user's controller (LoopController::user); without one the command is 0.
  void set_user_controller(const UserController<T>& user) noexcept { user_ = user; }

  // Start of a run: no force acting, the observer parked at x0 with the first floor sample, the
  // absolute velocities at rest.
  void reset(T a_u0, T x0_m = T(0)) noexcept {
    actuator_.reset(T(0));
    force_n_ = T(0);
    seat_velocity_.reset();
    floor_velocity_.reset();
    if (observer_ == ObserverKind::estimator) estimator_.reset(a_u_seen_(a_u0), x0_m);
  }

  // The force held over the next plant step (0 before the first sample), as the bus carries it.
  T force_n() const noexcept { return force_n_; }

  // One sample: a_u and the measured a_x and x_r of the sample; applied_force_n the force that
  // acted over the step into it; ideal_v_r and ideal_friction the plant's own (read only with
  // ObserverKind::ideal).
  UnitSample<T> step(T a_u, T a_x_measured, T x_r_measured, T applied_force_n, T ideal_v_r = T(0),
                     T ideal_friction_n = T(0)) noexcept {
    const T a_u_seen = a_u_seen_(a_u);
    T v_r = ideal_v_r, friction = ideal_friction_n;
    if (observer_ == ObserverKind::estimator) {
      // The estimator's model has no actuator input, but a force held over the step is a shift
      // of the input, a_u -> a_u - f/m (as in the core), and of the absolute acceleration the
      // model predicts, a_x -> a_x - f/m; the relative acceleration a_x - a_u is unchanged. Fed
      // so, the estimator's friction is the seat's F_f, not F_f - f_a (which would make a
      // friction feed-forward chase its own force). (The estimator holds its input first-order
      // between samples; the force steps at them: an approximation where the force changes.)
      const T shift = applied_force_n * inverse_mass_;
      const StateEstimate<T>& estimate =
          estimator_.step(a_u_seen - shift, a_x_measured - shift, x_r_measured);
      v_r = estimate.v_r_m_per_s;
      friction = estimate.friction_n;
    }
    UnitSample<T> sample;
    sample.sensed = SensorSample<T>{a_u_seen,
                                    a_x_measured,
                                    x_r_measured,
                                    v_r,
                                    seat_velocity_.step(a_x_measured),
                                    floor_velocity_.step(a_u_seen),
                                    friction};
    T command = T(0);
    if (controller_ == LoopController::hook) command = hook_.step(sample.sensed);
    if (controller_ == LoopController::user) command = user_.step(sample.sensed);
    if (compensate_) command = command + compensation_.step(sample.sensed);
    sample.command_n = command;
    force_n_ = force_sent_(actuator_.step(command));
    sample.next_force_n = force_n_;
    return sample;
  }

 private:
  LoopController controller_ = LoopController::passive;
  ObserverKind observer_ = ObserverKind::estimator;
  bool compensate_ = false;
  HookController<T> hook_;
  UserController<T> user_;
  FrictionCompensation<T> compensation_;
  Actuator<T> actuator_;
  AbsoluteVelocity<T> seat_velocity_, floor_velocity_;
  StateEstimator<T> estimator_;
  Quantiser<T> a_u_seen_, force_sent_;  // the bus's resolutions
  T inverse_mass_{};
  T force_n_{};
};

}  // namespace stickslip
