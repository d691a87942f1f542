// Event-driven reference solution of the seat oscillator: the yardstick the core's integrators are
// measured against ("Speed vs accuracy"). Host only (heap, exceptions, long double); independent
// of the core's step maps and event search - it shares only the parameter validation.
//
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u,    a_x = -(k x_r + b v_r + F_f)/m,
//   a_u piecewise linear between the samples (first-order hold).
//
// Method
// - linear, stick-slip and signum (= stick-slip with F_fs = F_fk: the Filippov solution): between
//   events the friction is constant and the input linear, so the motion is known in closed form
//   (particular ramp solution plus the free modal response, under-, critically or over-damped,
//   b = 0 included), evaluated in long double at any instant of a sample interval.
//   v_r = 0 instants are found by a safeguarded Newton iteration (bracketing, with the analytic
//   derivative a) on the closed form. The acceleration of a free mode has zeros exactly pi/omega_d
//   apart, so in a piece of at most pi/(2 omega_d) v_r has at most one extremum: a dip of |v_r| to
//   zero and back inside the piece is caught by locating that extremum (sign of a at both ends)
//   and testing v_r there. Break-away instants come from the linear F_L(t) in closed form. Any
//   number of events per sample interval (the loop runs to the interval's end).
// - stribeck and smooth: the nonlinear ODE is integrated by the adaptive Cash-Karp Runge-Kutta
//   5(4) of Boost.Odeint (tolerances 1e-15 relative, 1e-18 absolute), restarted at every sample
//   (the input has a kink there); inside an accepted step the state at any instant is a single
//   step of that length from the step's start (as accurate as the step), on which the same
//   bracketing event search runs. Stribeck uses the stick logic above; smooth laws have no events
//   (the rational form's steps end where v_r = 0, at the kink of its second derivative).
//   Runge-Kutta-Fehlberg 7(8) was tried first: its error estimate accepted steps 1e-5 off on
//   Stribeck scenes with v_S = 0.1 mm/s at dt = 4 ms (found by comparing dt with dt/64 runs).
#pragma once

#include <cstdint>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/models/end_stops.hpp"

namespace stickslip::host {

struct ReferenceTrace {
  // One entry per input sample; [0] is the initial state.
  std::vector<double> x_r_m, v_r_m_per_s, a_x_m_per_s2, friction_n;
  // Stuck at the sample (sticking laws and signum: at rest in the Filippov sense; friction_n is
  // then the holding force F_L and a_x = a_u exactly).
  std::vector<std::uint8_t> stuck;
  double stuck_time_s = 0;     // total time stuck, exact (from the located instants)
  std::uint64_t events = 0;    // stick, break-away and reversal events
  std::uint64_t contacts = 0;  // with end stops: contacts begun

  void resize(std::size_t rows) {
    for (auto* column : {&x_r_m, &v_r_m_per_s, &a_x_m_per_s2, &friction_n}) column->resize(rows);
    stuck.resize(rows);
  }
};

// Event-driven reference for params.model on the FOH input a_u sampled at params.dt_s, from x0, v0
// (a sticking model starts stuck when v0 == 0 and |F_L(0)| <= F_fs). params.integrator is ignored.
// Throws ConfigurationError (a HostError; the core's message) for parameters the core's
// configure() refuses with the exact integrator, and HostError for an empty or non-finite input or
// a non-finite initial state.
ReferenceTrace solve_reference(const OscillatorParams& params, const std::vector<double>& a_u,
                               double x0_m = 0.0, double v0_m_per_s = 0.0);

// The same with end stops (models/end_stops.hpp): free within +-travel, the Kelvin-Voigt stop
// beyond it. Three regions, each a linear oscillator in closed form; contact and release
// (|x_r| = travel), v_r = 0 and break-away are located on the closed form of the current region
// by a bracketing root finder (reference_end_stops.cpp). Laws: linear (a frictionless seat),
// signum, stick-slip and stribeck (whose slip phases are integrated by the adaptive Cash-Karp
// 5(4) above, region by region, with the same event searches on its steps). Throws
// ConfigurationError for smooth and for parameters EndStopOscillator::configure refuses,
// HostError as above.
ReferenceTrace solve_reference(const OscillatorParams& params, const EndStopParams& stops,
                               const std::vector<double>& a_u, double x0_m = 0.0,
                               double v0_m_per_s = 0.0);

// The same with an actuator force f_a (N, on the seat, upward positive) held constant over each
// sample interval: f_a_n[n] acts from t[n-1] to t[n] (f_a_n[0] only at the initial state), so
//   m dv_r/dt + b v_r + k x_r + F_f = -m a_u + f_a,   a_x = (f_a - (k x_r + b v_r + F_f))/m,
// and F_L = f_a - (m a_u + k x_r). A force held over an interval is a constant shift of that
// interval's input by -f_a/m: the closed forms above hold unchanged. f_a_n empty: no force; else
// one per sample, finite (HostError otherwise).
ReferenceTrace solve_reference_actuated(const OscillatorParams& params,
                                        const std::vector<double>& a_u,
                                        const std::vector<double>& f_a_n, double x0_m = 0.0,
                                        double v0_m_per_s = 0.0);

// The same with end stops and the actuator force (as solve_reference with EndStopParams): F_L =
// f_a - (m a_u + k x_r + F_stop); a jump of F_L beyond F_fs at an interval's start breaks away
// there.
ReferenceTrace solve_reference_actuated(const OscillatorParams& params, const EndStopParams& stops,
                                        const std::vector<double>& a_u,
                                        const std::vector<double>& f_a_n, double x0_m = 0.0,
                                        double v0_m_per_s = 0.0);

}  // namespace stickslip::host
