// The adaptive segments of the reference solver: Stribeck slip and the smooth laws, integrated
// by Cash-Karp 5(4) with the event search inside each step.
#include "reference_event_driver.hpp"

namespace stickslip::host::reference {

// Boost's steppers keep std::array temporaries that their default constructor leaves
// uninitialised (see reference_event_driver.hpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

Kinematics Solver::kinematics(const OdeSystem& system, const OdeState& s, double t) const {
  const double a =
      relative_acceleration(s[0], s[1], system.direction, system.a0 + system.a_slope * t);
  const double jerk = -(p_.stiffness_n_per_m * s[1] +
                        (p_.damping_ns_per_m + friction_slope(s[1], system.direction)) * a) /
                          p_.mass_kg -
                      system.a_slope;
  return {wide(s[0]), wide(s[1]), wide(a), wide(jerk)};
}

double Solver::ode_step(const OdeSystem& system, const OdeState& from, double t, double t_end,
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

Crossing Solver::slip_ode(Real a0, Real a1, Real tau, Real& tau_event) {
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
    const Crossing crossing = find_crossing(motion, d, 0, ka, wide(t_next - t), kb, ode_tolerance_);
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

void Solver::advance_smooth() {
  const double shift = narrow(force_offset(sample_));  // the held actuator force, f_a/m
  const double a0 = a_u_[sample_ - 1] - shift, a1 = a_u_[sample_] - shift;
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
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace stickslip::host::reference
