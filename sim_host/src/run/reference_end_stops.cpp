// The event-driven reference of the seat with end stops (reference_solver.hpp): three regions
// (free, upper stop, lower stop), each a linear oscillator with its own stiffness, damping and
// constant force, so that every slip or free phase is known in closed form (reference_closed_form
// .hpp) and every mode boundary is located on it by a bracketing root finder:
//   - v_r = 0 (stick or reversal; for the frictionless seat a turn): find_crossing, which also
//     catches a dip of v_r to 0 and back inside a piece;
//   - |x_r| = travel (contact, release): while slipping in direction d, v_r d > 0 until the next
//     v_r = 0 instant, so x_r is monotone there and a sign change of d (x_r - boundary) between the
//     phase start and that instant brackets the one crossing (safeguarded Newton, slope v_r);
//   - |F_L| = F_fs (break-away): F_L is linear in time while stuck, solved for directly.
// Stribeck: a slip phase has no closed form. It is integrated by Boost.Odeint's adaptive Cash-Karp
// 5(4) (tolerances 1e-15 relative, 1e-18 absolute, as the solver without stops does) in the
// region's right-hand side, restarted at every sample and event; inside an accepted step the state
// at any instant is one step of that length from the step's start, on which the same bracketing
// searches locate v_r = 0 (find_crossing, with the jerk including dF_f/dv) and |x_r| = travel.
// A step never spans more than a quarter period of its region, and near v_r = 0 it changes v_r by
// at most a tenth of v_S (the friction drops from F_fs to F_fk over a few v_S).
// An actuator force held over a sample interval shifts that interval's input by -f_a/m (the
// closed forms are unchanged); F_L may then jump at the interval's start, where the seat leaves
// at once if it exceeds F_fs.
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <fmt/format.h>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>

#include "reference_checks.hpp"
#include "reference_closed_form.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/models/end_stops.hpp"

namespace stickslip::host {
namespace reference {
namespace {

namespace odeint = boost::numeric::odeint;
using OdeState = std::array<double, 2>;  // x_r, v_r
using CashKarp54 = odeint::runge_kutta_cash_karp54<OdeState>;
using ControlledCashKarp54 = odeint::controlled_runge_kutta<CashKarp54>;
// The adaptive integration's tolerances and its step rule near v_r = 0 (those of
// reference_event_driver.hpp, for the same reasons).
constexpr double kOdeRelativeTolerance = 1e-15;
constexpr double kOdeAbsoluteTolerance = 1e-18;  // m and m/s
constexpr int kMaxRejectedSteps = 200;
constexpr double kVelocityBand = 20.0;
constexpr double kVelocityResolution = 0.1;

// Boost's steppers keep std::array temporaries that their default constructor leaves
// uninitialised (see reference_event_driver.hpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

class StopSolver {
 public:
  StopSolver(const OscillatorParams& p, const EndStopParams& stops, const std::vector<double>& a_u,
             const std::vector<double>* f_a_n)
      : p_(p),
        a_u_(a_u),
        f_a_(f_a_n),
        mass_(wide(p.mass_kg)),
        stiffness_(wide(p.stiffness_n_per_m)),
        damping_(wide(p.damping_ns_per_m)),
        stop_stiffness_(wide(stops.stiffness_n_per_m)),
        stop_damping_(wide(stops.damping_ns_per_m)),
        travel_(wide(stops.travel_m)),
        dt_(wide(p.dt_s)),
        free_(mass_, stiffness_, damping_),
        contact_(mass_, stiffness_ + stop_stiffness_, damping_ + stop_damping_),
        controlled_(
            odeint::make_controlled(kOdeAbsoluteTolerance, kOdeRelativeTolerance, CashKarp54())) {
    friction_ = p.model != FrictionModel::linear;
    stribeck_ = p.model == FrictionModel::stribeck;
    if (stribeck_) {
      inv_stribeck_velocity_ = 1.0 / p.stribeck_velocity_m_per_s;
      excess_ = p.static_friction_n - p.kinetic_friction_n;
      // A step stays inside a quarter period of the stiffer (contact) region.
      max_ode_step_ = p.dt_s;
      const double quarter =
          0.5 / std::sqrt((p.stiffness_n_per_m + stops.stiffness_n_per_m) / p.mass_kg);
      if (quarter < max_ode_step_) max_ode_step_ = quarter;
      ode_step_ = 1e-2 * max_ode_step_;
      ode_tolerance_ = 1e-15L * dt_;
    }
    kinetic_ = friction_ ? wide(p.kinetic_friction_n) : 0.0L;
    static_ = p.model == FrictionModel::signum ? kinetic_
                                               : (friction_ ? wide(p.static_friction_n) : 0.0L);
    tolerance_ = 4e-19L * dt_;
  }

  ReferenceTrace run(double x0, double v0) {
    const std::size_t count = a_u_.size();
    ReferenceTrace trace;
    trace.resize(count);
    x_ = wide(x0);
    v_ = wide(v0);
    region_ = x_ > travel_ ? 1 : (x_ < -travel_ ? -1 : 0);
    const Real limit = limit_force(shifted(0));
    if (v_ != 0) {
      direction_ = sign_of(v_);
    } else if (friction_ && std::fabs(limit) <= static_) {
      direction_ = 0;
    } else {
      direction_ = limit < 0 ? -1.0L : 1.0L;
    }
    record(trace, 0);
    for (std::size_t n = 1; n < count; ++n) {
      sample_ = n;
      // f_a[n] acts over the interval ending at sample n: both ends of its input shift.
      const Real offset = force_over_mass(n);
      advance(wide(a_u_[n - 1]) - offset, wide(a_u_[n]) - offset);
      record(trace, n);
    }
    trace.stuck_time_s = narrow(static_cast<Real>(whole_samples_stuck_) * dt_ + partial_stuck_s_);
    trace.events = events_;
    trace.contacts = contacts_;
    return trace;
  }

 private:
  // The stop's spring force at x in region c (its damping b_s v_r vanishes at rest).
  Real stop_spring(Real x, int c) const {
    return c == 0 ? 0.0L : stop_stiffness_ * (x - c * travel_);
  }
  // F_L = -(m a_u + k x_r + F_stop): the force friction must supply to hold the seat.
  Real limit_force(Real a_u) const {
    return -(mass_ * a_u + stiffness_ * x_ + stop_spring(x_, region_));
  }
  // f_a[n]/m, 0 without a force.
  Real force_over_mass(std::size_t n) const {
    return f_a_ == nullptr ? 0.0L : wide((*f_a_)[n]) / mass_;
  }
  // The input the seat feels at sample n: a_u - f_a/m.
  Real shifted(std::size_t n) const { return wide(a_u_[n]) - force_over_mass(n); }
  Real input_at(Real a0, Real a1, Real tau) const {
    if (a0 == a1) return a0;
    const Real phi = tau / dt_;
    return (1 - phi) * a0 + phi * a1;
  }

  void record(ReferenceTrace& trace, std::size_t n) const {
    trace.x_r_m[n] = narrow(x_);
    trace.v_r_m_per_s[n] = narrow(v_);
    if (direction_ == 0) {
      trace.friction_n[n] = narrow(limit_force(shifted(n)));
      trace.a_x_m_per_s2[n] = a_u_[n];
      trace.stuck[n] = 1;
      return;
    }
    const Real force =
        stribeck_ ? wide(slip_friction(narrow(v_), narrow(direction_))) : kinetic_ * direction_;
    const Real stop = region_ == 0 ? 0.0L : stop_spring(x_, region_) + stop_damping_ * v_;
    trace.friction_n[n] = narrow(force);
    trace.a_x_m_per_s2[n] =
        narrow(-(stiffness_ * x_ + damping_ * v_ + stop + force) / mass_ + force_over_mass(n));
    trace.stuck[n] = 0;
  }

  void count_event(int& in_sample) { count_sample_event(in_sample, sample_, p_.dt_s); }

  void advance(Real a0, Real a1) {
    Real tau = 0;
    int in_sample = 0;
    while (tau < dt_) {
      tau = direction_ == 0 ? stuck_until(a0, a1, tau, in_sample)
                            : move_until(a0, a1, tau, in_sample);
    }
  }

  // Stuck from tau (x_r fixed, F_L linear in time): to the end, or to the break-away instant.
  Real stuck_until(Real a0, Real a1, Real tau, int& in_sample) {
    const Real limit_now = limit_force(input_at(a0, a1, tau));
    if (std::fabs(limit_now) > static_) {
      // Only at an interval's start, where a change of the actuator force made F_L jump.
      direction_ = sign_of(limit_now);
      v_ = 0;
      ++events_;
      count_event(in_sample);
      return tau;
    }
    const Real limit_end = limit_force(a1);
    if (std::fabs(limit_end) <= static_) {
      if (tau == 0) {
        ++whole_samples_stuck_;
      } else {
        partial_stuck_s_ += dt_ - tau;
      }
      return dt_;
    }
    const Real d = sign_of(limit_end);
    Real tau_break = tau;
    if (a1 != a0) {
      const Real a_break = -(d * static_ + stiffness_ * x_ + stop_spring(x_, region_)) / mass_;
      tau_break = dt_ * ((a_break - a0) / (a1 - a0));
      if (!(tau_break > tau)) tau_break = tau;
      if (tau_break > dt_) tau_break = dt_;
    }
    partial_stuck_s_ += tau_break - tau;
    direction_ = d;
    v_ = 0;
    ++events_;
    count_event(in_sample);
    return tau_break;
  }

  // Moving from tau in direction d in the current region: to the end of the sample, or to the
  // first boundary (v_r = 0 or |x_r| = travel), whichever comes first. Returns the instant.
  // The stop boundary ahead of motion in direction d: entering one from the free stroke, or
  // leaving one moving back; false in contact moving further in (no boundary ahead).
  bool boundary_ahead(Real d, Real& boundary) const {
    if (region_ == 0) {
      boundary = d * travel_;
      return true;
    }
    if (d == -region_) {
      boundary = region_ * travel_;
      return true;
    }
    return false;
  }

  Real move_until(Real a0, Real a1, Real tau, int& in_sample) {
    if (stribeck_) return slip_ode_until(a0, a1, tau, in_sample);
    const Real d = direction_;
    const FreeModes& modes = region_ == 0 ? free_ : contact_;
    const Real offset = (kinetic_ * d - stop_stiffness_ * travel_ * region_) / mass_;
    const RampMotion motion(modes, x_, v_, input_at(a0, a1, tau), (a1 - a0) / dt_, offset);
    Real boundary = 0;
    const bool bounded = boundary_ahead(d, boundary);
    const Real length = dt_ - tau, piece = modes.max_piece_s();
    Real ta = 0;
    Kinematics ka = motion.start();
    while (ta < length) {
      Real tb = length;
      if (piece > 0 && tb - ta > piece) tb = ta + piece;
      const Kinematics kb = motion(tb);
      const Crossing turn = find_crossing(motion, d, ta, ka, tb, kb, tolerance_);
      const Real te = turn.found ? turn.tau : tb;
      if (bounded && d * (motion(te).x - boundary) >= 0) {
        // x_r d rises monotonically on [ta, te]: one crossing of the boundary.
        const auto ahead = [&](Real t) {
          const Kinematics k = motion(t);
          return std::array<Real, 2>{d * (boundary - k.x), -d * k.v};
        };
        const Real t_cross =
            d * (ka.x - boundary) >= 0 ? ta : solve_descending(ahead, ta, te, tolerance_);
        v_ = motion(t_cross).v;
        x_ = boundary;
        if (d * v_ < 0) v_ = 0;  // rounding at a turn that touches the boundary
        if (region_ == 0) {
          region_ = d > 0 ? 1 : -1;
          ++contacts_;
        } else {
          region_ = 0;
        }
        count_event(in_sample);
        return tau + t_cross < dt_ ? tau + t_cross : dt_;
      }
      if (turn.found) {
        x_ = motion(turn.tau).x;
        v_ = 0;
        count_event(in_sample);
        decide_at_rest(input_at(a0, a1, tau + turn.tau), d, turn.degenerate);
        return tau + turn.tau < dt_ ? tau + turn.tau : dt_;
      }
      ta = tb;
      ka = kb;
      if (d * ka.v < 0) ka.v = 0;
    }
    x_ = ka.x;
    v_ = ka.v;
    return dt_;
  }

  // --- Stribeck slip (adaptive integration) ---------------------------------------------------
  // exp(-(v/v_S)^2), 0 beyond 20 v_S and 1 below 1e-100 v_S (no intermediate underflows).
  double stribeck_shape(double v) const {
    const double r = std::fabs(v) * inv_stribeck_velocity_;
    if (r > 20.0) return 0.0;
    if (r < 1e-100) return 1.0;
    return std::exp(-r * r);
  }
  double slip_friction(double v, double d) const {
    return d * (p_.kinetic_friction_n + excess_ * stribeck_shape(v));
  }
  double friction_slope(double v, double d) const {
    const double r = std::fabs(v) * inv_stribeck_velocity_;
    if (r > 20.0 || r < 1e-100) return 0.0;
    return -d * excess_ * 2.0 * v * inv_stribeck_velocity_ * inv_stribeck_velocity_ *
           std::exp(-r * r);
  }
  // The right-hand side in region c, slipping in direction d, with the input a0 + slope t.
  struct OdeSystem {
    const StopSolver* solver;
    double a0, a_slope, direction;
    int region;
    void operator()(const OdeState& s, OdeState& ds, double t) const {
      ds[0] = s[1];
      ds[1] = solver->relative_acceleration(s[0], s[1], direction, region, a0 + a_slope * t);
    }
  };
  double relative_acceleration(double x, double v, double d, int c, double a_u) const {
    const double stop = c == 0 ? 0.0 : stops_stiffness() * (x - c * travel()) + stops_damping() * v;
    return -(p_.stiffness_n_per_m * x + p_.damping_ns_per_m * v + stop + slip_friction(v, d)) /
               p_.mass_kg -
           a_u;
  }
  double stops_stiffness() const { return narrow(stop_stiffness_); }
  double stops_damping() const { return narrow(stop_damping_); }
  double travel() const { return narrow(travel_); }
  Kinematics kinematics(const OdeSystem& system, const OdeState& s, double t) const {
    const double a = relative_acceleration(s[0], s[1], system.direction, system.region,
                                           system.a0 + system.a_slope * t);
    const double k = p_.stiffness_n_per_m + (system.region != 0 ? stops_stiffness() : 0.0);
    const double b = p_.damping_ns_per_m + (system.region != 0 ? stops_damping() : 0.0);
    const double jerk =
        -(k * s[1] + (b + friction_slope(s[1], system.direction)) * a) / p_.mass_kg -
        system.a_slope;
    return {wide(s[0]), wide(s[1]), wide(a), wide(jerk)};
  }

  // One accepted adaptive step from t (capped at t_end); returns the new time.
  double ode_step(const OdeSystem& system, const OdeState& from, double t, double t_end,
                  OdeState& to) {
    const double band = kVelocityBand * p_.stribeck_velocity_m_per_s;
    const double resolved = kVelocityResolution * p_.stribeck_velocity_m_per_s;
    for (int rejected = 0; rejected <= kMaxRejectedSteps; ++rejected) {
      double h = ode_step_ < max_ode_step_ ? ode_step_ : max_ode_step_;
      bool last = false;
      if (t + h >= t_end - 1e-12 * p_.dt_s) {
        h = t_end - t;
        last = true;
      }
      double t_new = t, h_next = h;
      if (controlled_.try_step(system, from, t_new, to, h_next) == odeint::success) {
        const double low = std::min(from[1], to[1]), high = std::max(from[1], to[1]);
        if (excess_ > 0.0 && low < band && high > -band && high - low > resolved) {
          ode_step_ = h * std::max(0.1, 0.9 * resolved / (high - low));
          continue;
        }
        if (excess_ > 0.0 && low < band && high > -band && h_next > 2.0 * h) h_next = 2.0 * h;
        if (!last || h_next < ode_step_) ode_step_ = h_next;
        return last ? t_end : t_new;
      }
      ode_step_ = h_next;
    }
    throw HostError(fmt::format(
        "reference solver: the adaptive integrator cannot meet its tolerance in the sample "
        "interval ending at sample {} (step {} s)",
        sample_, ode_step_));
  }

  // Stribeck slip from tau in direction d in the current region, adaptively: to the end of the
  // sample or to the first boundary (v_r = 0, |x_r| = travel). Returns the instant.
  Real slip_ode_until(Real a0, Real a1, Real tau, int& in_sample) {
    const Real d = direction_;
    const double t0 = narrow(tau), dt = p_.dt_s;
    const OdeSystem system{this, narrow(input_at(a0, a1, tau)), narrow((a1 - a0) / dt_), narrow(d),
                           region_};
    Real boundary = 0;
    const bool bounded = boundary_ahead(d, boundary);
    // Leaving rest the friction falls from F_fs within |v_r| ~ v_S: start small.
    if (v_ == 0 && ode_step_ > 1e-6 * dt) ode_step_ = 1e-6 * dt;
    double t = 0.0;  // time since tau
    const double length = dt - t0;
    OdeState state{narrow(x_), narrow(v_)};
    Kinematics ka = kinematics(system, state, t);
    while (t < length) {
      OdeState next{};
      const double t_next = ode_step(system, state, t, length, next);
      const Kinematics kb = kinematics(system, next, t_next);
      const auto motion = [&, t](Real offset) {
        if (offset <= 0) return kinematics(system, state, t);
        OdeState out{};
        controlled_.stepper().do_step(system, state, t, out, static_cast<double>(offset));
        return kinematics(system, out, t + static_cast<double>(offset));
      };
      const Crossing turn = find_crossing(motion, d, 0, ka, wide(t_next - t), kb, ode_tolerance_);
      const Real te = turn.found ? turn.tau : wide(t_next - t);
      if (bounded && d * (motion(te).x - boundary) >= 0) {
        const auto ahead = [&](Real u) {
          const Kinematics k = motion(u);
          return std::array<Real, 2>{d * (boundary - k.x), -d * k.v};
        };
        const Real u_cross =
            d * (ka.x - boundary) >= 0 ? Real(0) : solve_descending(ahead, 0, te, ode_tolerance_);
        v_ = motion(u_cross).v;
        x_ = boundary;
        if (d * v_ < 0) v_ = 0;
        if (region_ == 0) {
          region_ = d > 0 ? 1 : -1;
          ++contacts_;
        } else {
          region_ = 0;
        }
        count_event(in_sample);
        const Real at = tau + wide(t) + u_cross;
        return at < dt_ ? at : dt_;
      }
      if (turn.found) {
        x_ = motion(turn.tau).x;
        v_ = 0;
        count_event(in_sample);
        const Real at = tau + wide(t) + turn.tau;
        decide_at_rest(input_at(a0, a1, at < dt_ ? at : dt_), d, turn.degenerate);
        return at < dt_ ? at : dt_;
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
    return dt_;
  }

  // At a v_r = 0 instant after moving in direction d: stick if friction holds the load, else
  // move off against it. The frictionless seat turns (a turn is no friction event).
  void decide_at_rest(Real a_u, Real d, bool degenerate) {
    const Real limit = limit_force(a_u);
    if (!friction_) {
      direction_ = limit != 0 && !degenerate ? sign_of(limit) : -d;
      return;
    }
    ++events_;
    direction_ = degenerate || std::fabs(limit) <= static_ ? Real(0) : sign_of(limit);
  }

  const OscillatorParams& p_;
  const std::vector<double>& a_u_;
  const std::vector<double>* f_a_;  // null: no force
  Real mass_, stiffness_, damping_, stop_stiffness_, stop_damping_, travel_, dt_;
  FreeModes free_, contact_;
  bool friction_ = false, stribeck_ = false;
  Real kinetic_ = 0, static_ = 0, tolerance_ = 0;
  // Stribeck: the law and the adaptive integrator's state.
  double inv_stribeck_velocity_ = 0.0, excess_ = 0.0;
  double max_ode_step_ = 0.0, ode_step_ = 0.0;
  Real ode_tolerance_ = 0;
  ControlledCashKarp54 controlled_;
  Real x_ = 0, v_ = 0, direction_ = 0;
  int region_ = 0;
  std::size_t sample_ = 0;
  std::uint64_t events_ = 0, contacts_ = 0, whole_samples_stuck_ = 0;
  Real partial_stuck_s_ = 0;
};
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace
}  // namespace reference

ReferenceTrace solve_reference(const OscillatorParams& params, const EndStopParams& stops,
                               const std::vector<double>& a_u, double x0_m, double v0_m_per_s) {
  return solve_reference_actuated(params, stops, a_u, {}, x0_m, v0_m_per_s);
}

ReferenceTrace solve_reference_actuated(const OscillatorParams& params, const EndStopParams& stops,
                                        const std::vector<double>& a_u,
                                        const std::vector<double>& f_a_n, double x0_m,
                                        double v0_m_per_s) {
  OscillatorParams checked = params;
  checked.integrator = Integrator::exact;
  DiscreteModel free_model, contact_model;  // the validation only
  const ConfigResult configured = check_end_stops(checked, stops, free_model, contact_model);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  if (params.model == FrictionModel::smooth) {
    throw ConfigurationError(
        "reference solver: end stops are solved for the linear, signum, stick-slip and stribeck "
        "laws; smooth is not supported with end stops");
  }
  reference::check_inputs(a_u, f_a_n, x0_m, v0_m_per_s);
  reference::StopSolver solver(checked, stops, a_u, f_a_n.empty() ? nullptr : &f_a_n);
  return solver.run(x0_m, v0_m_per_s);
}

}  // namespace stickslip::host
