// The sticking laws' segments of the reference solver: stuck phases (F_L linear in time) and
// Coulomb slip phases, both in closed form, with the events between them.
#include "reference_event_driver.hpp"

namespace stickslip::host::reference {

// Boost's steppers keep std::array temporaries that their default constructor leaves
// uninitialised (see reference_event_driver.hpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

void Solver::advance_sticking(Real a0, Real a1) {
  const Real slope = (a1 - a0) / dt_;
  Real tau = 0;
  int events_in_sample = 0;
  while (tau < dt_) {
    if (direction_ == 0) {
      tau = stuck_until(a0, a1, tau, events_in_sample);
      continue;
    }
    Crossing crossing;
    Real tau_event = 0;
    if (law_ == Law::coulomb) {
      crossing = slip_closed_form(a0, a1, slope, tau, tau_event);
    } else {
      crossing = slip_ode(a0, a1, tau, tau_event);
    }
    if (!crossing.found) return;  // slipping to the end of the sample
    tau = tau_event;
    count_event(events_in_sample);
    decide_at_rest(input_at(a0, a1, tau), crossing.degenerate);
  }
}

Real Solver::stuck_until(Real a0, Real a1, Real tau, int& events_in_sample) {
  const Real limit_end = limit_force(a1);
  // Beyond F_fs already (an actuator force that changed at the sample: F_L jumps there): break
  // away now, the way F_L points now. Otherwise F_L is linear to the end: held if within there.
  const Real limit_now = limit_force(input_at(a0, a1, tau));
  const bool beyond_now = std::fabs(limit_now) > static_;
  if (std::fabs(limit_end) <= static_ && !beyond_now) {
    add_stuck(tau, dt_);
    return dt_;
  }
  const Real d = beyond_now ? sign_of(limit_now) : sign_of(limit_end);
  // F_L = d F_fs where a_u = -(d F_fs + k x)/m.
  Real tau_break = tau;
  if (a1 != a0 && !beyond_now) {
    const Real a_break = -(d * static_ + stiffness_ * x_) / mass_;
    tau_break = dt_ * ((a_break - a0) / (a1 - a0));
    if (!(tau_break > tau)) tau_break = tau;
    if (tau_break > dt_) tau_break = dt_;
  }
  add_stuck(tau, tau_break);
  direction_ = d;
  v_ = 0;
  count_event(events_in_sample);
  return tau_break;
}

Crossing Solver::slip_closed_form(Real a0, Real a1, Real slope, Real tau, Real& tau_event) {
  const Real d = direction_;
  const RampMotion motion(modes_, x_, v_, input_at(a0, a1, tau), slope, kinetic_ * d / mass_);
  const Real length = dt_ - tau;
  Real ta = 0;
  Kinematics ka = motion.start();
  while (ta < length) {
    Real tb = length;
    if (piece_ > 0 && tb - ta > piece_) tb = ta + piece_;
    const Kinematics kb = tau == 0 && tb == length ? motion.at(full_sample_, tb) : motion(tb);
    const Crossing crossing = find_crossing(motion, d, ta, ka, tb, kb, closed_form_tolerance_);
    if (crossing.found) {
      x_ = motion(crossing.tau).x;
      v_ = 0;
      tau_event = tau + crossing.tau;
      if (tau_event > dt_) tau_event = dt_;
      return crossing;
    }
    ta = tb;
    ka = kb;
    // Rising or departing w that rounds below 0 at a piece end is at rest, not reversed.
    if (d * ka.v < 0) ka.v = 0;
  }
  x_ = ka.x;
  v_ = ka.v;
  return {};
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace stickslip::host::reference
