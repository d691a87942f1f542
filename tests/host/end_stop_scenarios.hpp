// What the end-stop tests share (test_end_stop_exactness.cpp, test_end_stop_actuator.cpp,
// test_end_stop_stribeck.cpp, test_end_stop_fixed.cpp, test_end_stop_fixed32.cpp): a seeded
// wide-band floor at 1 ms, the reference seat with a chosen friction and damping, stops of 2e5 N/m
// at a chosen travel, a model's history on an input, and how far one history is from another.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "../core/oracles.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip::test::end_stop {

constexpr double kDt = 1e-3;

// A seeded floor (harmonic: at frequency_hz), 20 s unless told.
inline std::vector<double> floor_signal(host::SignalKind kind, double rms, double dt_s,
                                        std::uint64_t seed, double frequency_hz = 0.0,
                                        double duration_s = 20.0) {
  host::GeneratorSpec spec;
  spec.kind = kind;
  spec.rms_m_per_s2 = rms;
  spec.frequency_hz = frequency_hz;
  spec.duration_s = duration_s;
  spec.dt_s = dt_s;
  spec.seed = seed;
  return host::generate_signal(spec);
}

inline std::vector<double> wideband(double rms, double duration_s, std::uint64_t seed) {
  return floor_signal(host::SignalKind::wideband, rms, kDt, seed, 0.0, duration_s);
}

// White noise, a new level every sample, uniform in +-level_m_per_s2 (20 s: 20,001 samples at
// kDt): the floor on which v_r crosses 0 and back inside one step.
inline std::vector<double> white_noise(double level_m_per_s2, std::uint64_t seed,
                                       double dt_s = kDt) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> level(-level_m_per_s2, level_m_per_s2);
  std::vector<double> a_u(static_cast<std::size_t>(std::lround(20.0 / dt_s)) + 1);
  for (double& a : a_u) a = level(rng);
  return a_u;
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

// How far a run is from a reference run over `duration_s`.
struct Deviation {
  double x = 0.0;     // max |x - x_ref| / max |x_ref|
  double a_x = 0.0;   // RMS of a_x - a_x,ref over RMS of a_x,ref
  double t_ax = 0.0;  // relative difference of T_ax = RMS a_x / RMS a_u
  double p = 0.0;     // difference of the fraction of time stuck
};

inline Deviation deviation(const std::vector<double>& x, const std::vector<double>& a_x,
                           double stuck_s, const std::vector<double>& x_ref,
                           const std::vector<double>& a_ref, double stuck_ref_s,
                           double duration_s) {
  Deviation d;
  double x_scale = 0.0, ex = 0.0, ea = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    x_scale = std::max(x_scale, std::fabs(x_ref[n]));
    ex = std::max(ex, std::fabs(x[n] - x_ref[n]));
    ea += (a_x[n] - a_ref[n]) * (a_x[n] - a_ref[n]);
  }
  const double a_scale = rms(a_ref);
  d.x = ex / x_scale;
  d.a_x = std::sqrt(ea / static_cast<double>(x.size())) / a_scale;
  d.t_ax = std::fabs(rms(a_x) - a_scale) / a_scale;
  d.p = std::fabs(stuck_s - stuck_ref_s) / duration_s;
  return d;
}

inline Deviation deviation(const History& h, const History& ref, double duration_s) {
  return deviation(h.x, h.a_x, h.stuck_s, ref.x, ref.a_x, ref.stuck_s, duration_s);
}

// The figures, with STICKSLIP_TEST_MARGINS=1.
inline void print(const char* what, const Deviation& d) {
  if (std::getenv("STICKSLIP_TEST_MARGINS") == nullptr) return;
  std::printf("\n    [figure] %s: x %.3e, a_x rms %.3e, T_ax %.3e, p %.3e", what, d.x, d.a_x,
              d.t_ax, d.p);
}

// The RMS of x_r of the seat without stops (double) on a_u: the travel that puts the stops in
// frequent contact.
template <typename Law>
double rms_free_stroke(const OscillatorParams& p, const std::vector<double>& a_u) {
  Oscillator<double, Law> plain;
  if (!plain.configure(p).ok()) return 0.0;
  return rms(run_history(plain, a_u).x);
}

}  // namespace stickslip::test::end_stop
