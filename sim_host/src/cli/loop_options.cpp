#include "loop_options.hpp"

#include <fmt/format.h>

#include "command.hpp"
#include "stickslip/host/error.hpp"

namespace stickslip::host {

void add_sensor_noise_options(Options& command, ClosedLoopSetup& setup) {
  command
      .add_option("--a-x-noise", setup.a_x_noise_m_per_s2,
                  "seat accelerometer noise, RMS per sample, m/s^2 (default 0)")
      ->check(OptionCheck::non_negative);
  command
      .add_option("--x-r-noise", setup.x_r_noise_m,
                  "travel sensor noise, RMS per sample, m (default 0)")
      ->check(OptionCheck::non_negative);
}

void LoopControllerOptions::add_to(Options& command, ClosedLoopSetup& setup) {
  command.add_option("--controller", controller_,
                     "passive | skyhook | groundhook | skyhook-semi | groundhook-semi | "
                     "friction-compensation (default passive)");
  command.add_option("--gain", setup.gain_ns_per_m, "hook gain c, N s/m (default 1500)")
      ->check(OptionCheck::non_negative);
  command
      .add_option("--b-min", setup.min_damping_ns_per_m,
                  "semi-active damper's least damping, N s/m (default 0)")
      ->check(OptionCheck::non_negative);
  command
      .add_option("--b-max", setup.max_damping_ns_per_m,
                  "semi-active damper's most damping, N s/m (default 3000)")
      ->check(OptionCheck::non_negative);
  command.add_option("--friction-compensation", setup.friction_compensation,
                     "fraction of the observer's friction estimate fed forward, in [0, 1] "
                     "(default 0; friction-compensation alone: 0.8)");
  command
      .add_option("--force-limit", setup.force_limit_n, "actuator force limit, N (default 1000)")
      ->check(OptionCheck::positive);
  command
      .add_option("--actuator-lag", setup.actuator_lag_s,
                  "actuator first-order lag time constant, s (default 0: ideal)")
      ->check(OptionCheck::non_negative);
  command.add_option("--observer", observer_,
                     "estimator (state estimator on the measured a_x, x_r; default) | ideal "
                     "(the controller reads the plant's own v_r and F_f)");
  add_sensor_noise_options(command, setup);
}

void LoopControllerOptions::resolve(const Options& command, ClosedLoopSetup& setup) const {
  if (!parse_controller(controller_, setup.controller)) {
    throw UsageError("--controller " + controller_ + ": expected " +
                     join_choices(controller_names(), ", ", " or ") +
                     did_you_mean(controller_, controller_names()));
  }
  if (observer_ == "estimator") {
    setup.observer = ObserverKind::estimator;
  } else if (observer_ == "ideal") {
    setup.observer = ObserverKind::ideal;
  } else {
    throw UsageError("--observer " + observer_ + ": expected estimator or ideal");
  }
  if (given(command, "--friction-compensation") &&
      !(setup.friction_compensation >= 0.0 && setup.friction_compensation <= 1.0)) {
    throw UsageError(fmt::format("--friction-compensation: must be a fraction in [0, 1], got {}",
                                 setup.friction_compensation));
  }
  if (setup.controller == ControllerChoice::friction_compensation &&
      !given(command, "--friction-compensation")) {
    setup.friction_compensation = 0.8;
  }
}

}  // namespace stickslip::host
