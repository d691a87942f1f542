#include "tradeoff/peers.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>
#include <boost/numeric/odeint.hpp>

namespace stickslip::tradeoff {
namespace {

namespace odeint = boost::numeric::odeint;
using State = std::array<double, 2>;  // x_r, v_r

struct Coefficients {
  double mass_kg, stiffness, damping, k_m, b_m, inv_m;
  double kinetic_n, static_n, smoothing_c, dt_s;

  explicit Coefficients(const OscillatorParams& p)
      : mass_kg(p.mass_kg),
        stiffness(p.stiffness_n_per_m),
        damping(p.damping_ns_per_m),
        k_m(p.stiffness_n_per_m / p.mass_kg),
        b_m(p.damping_ns_per_m / p.mass_kg),
        inv_m(1.0 / p.mass_kg),
        kinetic_n(p.kinetic_friction_n),
        static_n(p.static_friction_n),
        smoothing_c(p.smoothing_constant_s_per_m),
        dt_s(p.dt_s) {}
};

// First-order-hold input over the current sample interval [t0, t0 + dt].
struct Interval {
  double t0 = 0.0, a0 = 0.0, slope = 0.0;
  double at(double t) const noexcept { return a0 + slope * (t - t0); }
};

// m v' = -k x - b v - F_fk tanh(c v) - m a_u
struct SmoothRhs {
  const Coefficients* q;
  Interval in;
  void operator()(const State& s, State& d, double t) const {
    d[0] = s[1];
    d[1] = -q->k_m * s[0] - q->b_m * s[1] -
           q->inv_m * q->kinetic_n * std::tanh(q->smoothing_c * s[1]) - in.at(t);
  }
};

// Slipping with a constant friction force.
struct SlipRhs {
  const Coefficients* q;
  Interval in;
  double friction_n;
  void operator()(const State& s, State& d, double t) const {
    d[0] = s[1];
    d[1] = -q->k_m * s[0] - q->b_m * s[1] - q->inv_m * friction_n - in.at(t);
  }
};

StepOutput<double> slip_output(const Coefficients& q, const State& s, double friction_n) {
  StepOutput<double> out{};
  out.x_r_m = s[0];
  out.v_r_m_per_s = s[1];
  out.friction_n = friction_n;
  out.a_x_m_per_s2 = -(q.stiffness * s[0] + q.damping * s[1] + friction_n) * q.inv_m;
  return out;
}

// Step attempts per sample interval before a controlled peer gives up (the state then turns NaN,
// which the harness reports as unstable): an integration that cannot advance must not hang the run.
constexpr int kMaxAttemptsPerSample = 100000;

void give_up(State& s) {
  s[0] = s[1] = std::numeric_limits<double>::quiet_NaN();
}

// The time of sample n: from the index, never accumulated.
double sample_time(std::uint64_t n, double dt) {
  return static_cast<double>(n) * dt;
}

// runge_kutta4, one step per sample.
class Rk4Smooth {
 public:
  explicit Rk4Smooth(const Coefficients& q) : q_(q) {}
  void reset(double x0, double v0, double a0) {
    s_ = {x0, v0};
    a_prev_ = a0;
    n_ = 0;
  }
  StepOutput<double> current() const { return output(); }
  StepOutput<double> step(double a1) {
    const double t0 = sample_time(n_, q_.dt_s);
    SmoothRhs rhs{&q_, {t0, a_prev_, (a1 - a_prev_) / q_.dt_s}};
    stepper_.do_step(rhs, s_, t0, q_.dt_s);
    ++n_;
    a_prev_ = a1;
    return output();
  }

 private:
  StepOutput<double> output() const {
    return slip_output(q_, s_, q_.kinetic_n * std::tanh(q_.smoothing_c * s_[1]));
  }
  Coefficients q_;
  odeint::runge_kutta4<State> stepper_;
  State s_{};
  double a_prev_ = 0.0;
  std::uint64_t n_ = 0;
};

// Controlled runge_kutta_dopri5 over each sample interval; the step size carries over.
class Dopri5Smooth {
 public:
  Dopri5Smooth(const Coefficients& q, double tolerance)
      : q_(q),
        stepper_(
            odeint::make_controlled(tolerance, tolerance, odeint::runge_kutta_dopri5<State>())) {}
  void reset(double x0, double v0, double a0) {
    s_ = {x0, v0};
    a_prev_ = a0;
    n_ = 0;
    h_ = q_.dt_s;
    stepper_.reset();
  }
  StepOutput<double> current() const { return output(); }
  StepOutput<double> step(double a1) {
    const double t0 = sample_time(n_, q_.dt_s), t1 = sample_time(n_ + 1, q_.dt_s);
    SmoothRhs rhs{&q_, {t0, a_prev_, (a1 - a_prev_) / q_.dt_s}};
    double t = t0;
    for (int attempts = 0; t1 - t > 1e-12 * q_.dt_s; ++attempts) {
      if (attempts == kMaxAttemptsPerSample || !std::isfinite(s_[1])) {
        give_up(s_);
        break;
      }
      double h = std::min(h_, t1 - t);
      const bool clipped = h < h_;
      if (stepper_.try_step(rhs, s_, t, h) == odeint::success) {
        if (!clipped) h_ = h;  // the controller's proposal for the next step
      } else {
        h_ = h;
      }
    }
    ++n_;
    a_prev_ = a1;
    return output();
  }

 private:
  StepOutput<double> output() const {
    return slip_output(q_, s_, q_.kinetic_n * std::tanh(q_.smoothing_c * s_[1]));
  }
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<State>>;
  Coefficients q_;
  Controlled stepper_;
  State s_{};
  double a_prev_ = 0.0, h_ = 0.0;
  std::uint64_t n_ = 0;
};

// Stick-slip the straightforward way: controlled dopri5 while slipping; after every accepted step
// check v_r for a sign change and bisect the step (re-integrating from its start) to the event
// time tolerance; there stick if |F_L| <= F_fs, else reverse. While stuck, check |F_L| = F_fs at
// the end of each sample interval and bisect in time for the break-away.
class Dopri5Events {
 public:
  Dopri5Events(const Coefficients& q, double tolerance)
      : q_(q),
        time_tolerance_s_(tolerance * kPeerEventTimeTolerancePerTolerance),
        stepper_(
            odeint::make_controlled(tolerance, tolerance, odeint::runge_kutta_dopri5<State>())) {}
  void reset(double x0, double v0, double a0) {
    s_ = {x0, v0};
    a_prev_ = a0;
    n_ = 0;
    h_ = q_.dt_s;
    budget_hits_ = 0;
    stepper_.reset();
    const double limit = limit_force(a0);
    direction_ = v0 != 0.0 ? (v0 > 0.0 ? 1 : -1)
                           : (std::fabs(limit) <= q_.static_n ? 0 : (limit > 0.0 ? 1 : -1));
    stuck_fraction_ = 0.0;
    events_ = 0;
  }
  StepOutput<double> current() const { return output(a_prev_); }
  StepOutput<double> step(double a1) {
    const double t0 = sample_time(n_, q_.dt_s), t1 = sample_time(n_ + 1, q_.dt_s);
    const Interval in{t0, a_prev_, (a1 - a_prev_) / q_.dt_s};
    double t = t0, stuck_s = 0.0;
    int events = 0;
    for (int attempts = 0; t1 - t > 1e-12 * q_.dt_s; ++attempts) {
      if (attempts == kMaxAttemptsPerSample || !std::isfinite(s_[1])) {
        give_up(s_);
        break;
      }
      if (direction_ == 0) {
        if (std::fabs(limit_force(in.at(t1))) <= q_.static_n) {
          stuck_s += t1 - t;
          t = t1;
          break;
        }
        // Break-away inside [t, t1]: bisect on |F_L(t)| - F_fs.
        double lo = t, hi = t1;
        while (hi - lo > time_tolerance_s_) {
          const double mid = 0.5 * (lo + hi);
          (std::fabs(limit_force(in.at(mid))) > q_.static_n ? hi : lo) = mid;
        }
        stuck_s += hi - t;
        t = hi;
        direction_ = limit_force(in.at(t)) > 0.0 ? 1 : -1;
        s_[1] = 0.0;
        stepper_.reset();
        ++events;
        continue;
      }
      SlipRhs rhs{&q_, in, q_.kinetic_n * direction_};
      const State start = s_;
      const double t_start = t;
      double h = std::min(h_, t1 - t);
      const bool clipped = h < h_;
      if (stepper_.try_step(rhs, s_, t, h) != odeint::success) {
        h_ = h;
        continue;
      }
      if (!clipped) h_ = h;
      if (s_[1] * direction_ >= 0.0) continue;
      if (events >= kPeerMaxEventsPerSample) {
        ++budget_hits_;
        continue;
      }
      // v_r changed sign inside the step: bisect on the step length from the step's start.
      State dxdt_start{}, trial{}, dxdt_trial{};
      rhs(start, dxdt_start, t_start);
      double lo = 0.0, hi = t - t_start;
      while (hi - lo > time_tolerance_s_) {
        const double mid = 0.5 * (lo + hi);
        plain_.do_step(rhs, start, dxdt_start, t_start, trial, dxdt_trial, mid);
        (trial[1] * direction_ < 0.0 ? hi : lo) = mid;
      }
      plain_.do_step(rhs, start, dxdt_start, t_start, s_, dxdt_trial, hi);
      s_[1] = 0.0;
      t = t_start + hi;
      const double limit = limit_force(in.at(t));
      direction_ = std::fabs(limit) <= q_.static_n ? 0 : (limit > 0.0 ? 1 : -1);
      stepper_.reset();
      ++events;
    }
    ++n_;
    a_prev_ = a1;
    stuck_fraction_ = stuck_s / q_.dt_s;
    events_ = events;
    return output(a1);
  }
  std::uint64_t budget_hits() const { return budget_hits_; }

 private:
  double limit_force(double a_u) const { return -(q_.mass_kg * a_u + q_.stiffness * s_[0]); }
  StepOutput<double> output(double a_u) const {
    StepOutput<double> out{};
    if (direction_ == 0) {
      out.x_r_m = s_[0];
      out.a_x_m_per_s2 = a_u;
      out.friction_n = limit_force(a_u);
      out.stuck = true;
    } else {
      out = slip_output(q_, s_, q_.kinetic_n * direction_);
    }
    out.stuck_fraction = stuck_fraction_;
    out.stuck_time_s = stuck_fraction_ * q_.dt_s;
    out.events = static_cast<std::uint8_t>(std::min(events_, 255));
    return out;
  }

  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<State>>;
  Coefficients q_;
  double time_tolerance_s_;
  Controlled stepper_;
  odeint::runge_kutta_dopri5<State> plain_;
  State s_{};
  double a_prev_ = 0.0, h_ = 0.0, stuck_fraction_ = 0.0;
  int direction_ = 0, events_ = 0;
  std::uint64_t n_ = 0, budget_hits_ = 0;
};

template <typename Peer>
Outcome measure_peer(Peer& peer, const std::vector<double>& a_u, bool has_stick_state,
                     const Reference& physics, const Timing& timing) {
  Outcome outcome;
  outcome.trace = trace_stream(peer, a_u, has_stick_state);
  if (!outcome.trace.finite) {
    outcome.status = "unstable";
    outcome.note = "non-finite state";
    return outcome;
  }
  const std::string reason = blow_up_reason(outcome.trace, physics);
  if (!reason.empty()) {
    outcome.status = "unstable";
    outcome.note = reason;
    return outcome;
  }
  outcome.timing = time_stream(peer, a_u, timing);
  return outcome;
}

}  // namespace

Outcome run_peer(const PeerSpec& peer, const OscillatorParams& scene_params,
                 const std::vector<double>& a_u, const Reference& physics, const Timing& timing) {
  const Coefficients q(scene_params);
  switch (peer.kind) {
    case PeerKind::rk4_smooth: {
      Rk4Smooth model(q);
      return measure_peer(model, a_u, false, physics, timing);
    }
    case PeerKind::dopri5_smooth: {
      Dopri5Smooth model(q, peer.tolerance);
      return measure_peer(model, a_u, false, physics, timing);
    }
    case PeerKind::dopri5_events: {
      Dopri5Events model(q, peer.tolerance);
      Outcome outcome = measure_peer(model, a_u, true, physics, timing);
      if (model.budget_hits() > 0) {
        outcome.note = fmt::format("event budget hit {} times", model.budget_hits());
      }
      return outcome;
    }
  }
  return {};
}

}  // namespace stickslip::tradeoff
