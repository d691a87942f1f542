// The event-driven reference solver (see reference_solver.hpp for the method): the per-sample
// loop of the event driver and the checks of solve_reference().
#include "stickslip/host/run/reference_solver.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "reference_checks.hpp"
#include "reference_event_driver.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/integrators/discretisation.hpp"

namespace stickslip::host {
namespace reference {

// Boost's steppers keep std::array temporaries that their default constructor leaves
// uninitialised (see reference_event_driver.hpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

ReferenceTrace Solver::run(double x0, double v0) {
  const std::size_t count = a_u_.size();
  ReferenceTrace trace;
  trace.resize(count);

  x_ = wide(x0);
  v_ = wide(v0);
  direction_ = 0;
  if (law_ == Law::coulomb || law_ == Law::stribeck) {
    const Real limit = limit_force(wide(a_u_[0]) - force_offset(0));
    if (v_ != 0) {
      direction_ = sign_of(v_);
    } else if (std::fabs(limit) > static_) {
      direction_ = sign_of(limit);
    }
  } else {
    direction_ = 1;  // never stuck
  }
  record(trace, 0);
  for (std::size_t n = 1; n < count; ++n) {
    sample_ = n;
    const Real offset = force_offset(n);
    const Real a0 = wide(a_u_[n - 1]) - offset, a1 = wide(a_u_[n]) - offset;
    switch (law_) {
      case Law::linear:
        advance_linear(a0, a1);
        break;
      case Law::coulomb:
      case Law::stribeck:
        advance_sticking(a0, a1);
        break;
      case Law::smooth:
        advance_smooth();
        break;
    }
    record(trace, n);
  }
  trace.stuck_time_s = narrow(static_cast<Real>(whole_samples_stuck_) * dt_ + partial_stuck_s_);
  trace.events = events_;
  return trace;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

void check_inputs(const std::vector<double>& a_u, const std::vector<double>& f_a_n, double x0_m,
                  double v0_m_per_s) {
  if (a_u.empty()) throw HostError("reference solver: the input has no samples");
  for (std::size_t n = 0; n < a_u.size(); ++n) {
    if (!std::isfinite(a_u[n])) {
      throw HostError(fmt::format("reference solver: a_u[{}] = {} is not finite", n, a_u[n]));
    }
  }
  if (!f_a_n.empty() && f_a_n.size() != a_u.size()) {
    throw HostError(fmt::format("reference solver: {} actuator forces for {} input samples",
                                f_a_n.size(), a_u.size()));
  }
  for (std::size_t n = 0; n < f_a_n.size(); ++n) {
    if (!std::isfinite(f_a_n[n])) {
      throw HostError(fmt::format("reference solver: f_a[{}] = {} is not finite", n, f_a_n[n]));
    }
  }
  if (!std::isfinite(x0_m) || !std::isfinite(v0_m_per_s)) {
    throw HostError(
        fmt::format("reference solver: the initial state x0 = {} m, v0 = {} m/s is not finite",
                    x0_m, v0_m_per_s));
  }
}

void count_sample_event(int& events_in_sample, std::size_t sample, double dt_s) {
  if (++events_in_sample > kMaxEventsPerSample) {
    throw HostError(fmt::format(
        "reference solver: more than {} events in the sample interval ending at sample {} "
        "(t = {} s): a degenerate scene",
        kMaxEventsPerSample, sample, static_cast<double>(sample) * dt_s));
  }
}

}  // namespace reference

ReferenceTrace solve_reference(const OscillatorParams& params, const std::vector<double>& a_u,
                               double x0_m, double v0_m_per_s) {
  return solve_reference_actuated(params, a_u, {}, x0_m, v0_m_per_s);
}

ReferenceTrace solve_reference_actuated(const OscillatorParams& params,
                                        const std::vector<double>& a_u,
                                        const std::vector<double>& f_a_n, double x0_m,
                                        double v0_m_per_s) {
  OscillatorParams checked = params;
  checked.integrator = Integrator::exact;
  DiscreteModel model;  // only the validation is used; the solution below is independent of it
  const ConfigResult configured = discretise(checked, model);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  reference::check_inputs(a_u, f_a_n, x0_m, v0_m_per_s);
  reference::Solver solver(checked, a_u, f_a_n.empty() ? nullptr : &f_a_n);
  return solver.run(x0_m, v0_m_per_s);
}

}  // namespace stickslip::host
