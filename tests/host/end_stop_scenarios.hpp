// What the end-stop tests share (test_end_stop_exactness.cpp, test_end_stop_actuator.cpp,
// test_end_stop_stribeck.cpp, test_end_stop_fixed.cpp): a seeded wide-band floor at 1 ms, the
// reference seat with a chosen friction and damping, stops of 2e5 N/m at a chosen travel, and a
// model's history on an input.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "../core/oracles.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip::test::end_stop {

constexpr double kDt = 1e-3;

inline std::vector<double> wideband(double rms, double duration_s, std::uint64_t seed) {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::wideband;
  spec.rms_m_per_s2 = rms;
  spec.duration_s = duration_s;
  spec.dt_s = kDt;
  spec.seed = seed;
  return host::generate_signal(spec);
}

inline OscillatorParams seat(FrictionModel model, double damping, double kinetic_n,
                             double static_n) {
  OscillatorParams p = reference_params(model, Integrator::exact, kDt, damping);
  p.kinetic_friction_n = kinetic_n;
  p.static_friction_n = static_n;
  return p;
}

inline EndStopParams stops(double travel_m, double damping) {
  EndStopParams s;
  s.travel_m = travel_m;
  s.stiffness_n_per_m = 2.0e5;
  s.damping_ns_per_m = damping;
  return s;
}

// A model's run on a_u from rest, in double: x_r, a_x, friction, the stuck flag and the stuck
// fraction of every `keep`-th sample (row 0 the initial state, stuck fraction 0 there), the time
// stuck over all steps, and counters the caller fills in.
struct History {
  std::vector<double> x, a_x, friction, stuck_fraction;
  std::vector<std::uint8_t> stuck;
  double stuck_s = 0.0;
  std::uint64_t contacts = 0, budget_exhausted = 0, saturated = 0, resets = 0;
};

template <typename Model>
History run_history(Model& model, const std::vector<double>& a_u, double dt_s = kDt,
                    std::size_t keep = 1) {
  using T = typename Model::Scalar;
  using S = ScalarTraits<T>;
  History h;
  const auto record = [&h](const StepOutput<T>& out, double stuck_fraction) {
    h.x.push_back(S::to_double(out.x_r_m));
    h.a_x.push_back(S::to_double(out.a_x_m_per_s2));
    h.friction.push_back(S::to_double(out.friction_n));
    h.stuck.push_back(out.stuck ? 1 : 0);
    h.stuck_fraction.push_back(stuck_fraction);
  };
  model.reset(T(0.0), T(0.0), T(a_u[0]));
  record(model.current(), 0.0);
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<T> out = model.step(T(a_u[n]));
    const double fraction = S::to_double(out.stuck_fraction);
    h.stuck_s += fraction * dt_s;
    if (n % keep == 0) record(out, fraction);
  }
  return h;
}

// The model's history with its contact and event-budget counters.
template <typename Model>
History counted_history(Model& model, const std::vector<double>& a_u, double dt_s = kDt,
                        std::size_t keep = 1) {
  History h = run_history(model, a_u, dt_s, keep);
  h.contacts = model.contacts();
  h.budget_exhausted = model.event_budget_exhausted();
  return h;
}

inline double rms(const std::vector<double>& a) {
  double sum = 0.0;
  for (const double v : a) sum += v * v;
  return std::sqrt(sum / static_cast<double>(a.size()));
}

}  // namespace stickslip::test::end_stop
