// The loop that is timed and counted: what a streaming user runs per sample (step + running
// statistics), no I/O, no allocation. Shared by the library's oscillators and the Odeint peers,
// which offer the same reset/current/step interface.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"
#include "tradeoff/combinations.hpp"

#if defined(__GNUC__) || defined(__clang__)
#define STICKSLIP_TRADEOFF_NOINLINE __attribute__((noinline))
#else
#define STICKSLIP_TRADEOFF_NOINLINE
#endif

namespace stickslip::tradeoff {

// Keeps a value alive for the optimiser without storing it anywhere.
template <typename T>
inline void keep(const T& value) noexcept {
#if defined(__GNUC__) || defined(__clang__)
  asm volatile("" : : "g"(&value) : "memory");
#else
  static volatile T sink;
  sink = value;
#endif
}

// One pass over the input: reset, then step() and the statistics for every sample. Not inlined so
// that the profile shows it as one function. Returns T_ax (it must be used).
template <typename Model, typename T>
STICKSLIP_TRADEOFF_NOINLINE double stream(Model& model, const T* a_u, std::size_t count,
                                          RunningStatistics<T>& statistics) {
  model.reset(T(0), T(0), a_u[0]);
  statistics.reset();
  statistics.add_sample(a_u[0], model.current().a_x_m_per_s2);
  for (std::size_t n = 1; n < count; ++n) {
    const StepOutput<T> out = model.step(a_u[n]);
    statistics.add_sample(a_u[n], out.a_x_m_per_s2);
    statistics.add_step(out.stuck_fraction);
  }
  return statistics.transmissibility();
}

struct TimingResult {
  double median_ns = 0.0, min_ns = 0.0, max_ns = 0.0;  // per step
  int repetitions = 0;
};

// Warm-up pass, then `timing.repetitions` repetitions of at least timing.min_repetition_s each
// (whole passes over the input); the median, fastest and slowest per step.
template <typename Model, typename T>
TimingResult time_stream(Model& model, const std::vector<T>& a_u, const Timing& timing) {
  using Clock = std::chrono::steady_clock;
  RunningStatistics<T> statistics;
  const std::size_t steps = a_u.size() - 1;
  auto start = Clock::now();
  keep(stream(model, a_u.data(), a_u.size(), statistics));
  const double once_s = std::chrono::duration<double>(Clock::now() - start).count();
  const int passes =
      once_s >= timing.min_repetition_s
          ? 1
          : static_cast<int>(std::ceil(timing.min_repetition_s / std::max(once_s, 1e-9)));
  std::vector<double> ns;
  for (int r = 0; r < timing.repetitions; ++r) {
    start = Clock::now();
    for (int pass = 0; pass < passes; ++pass)
      keep(stream(model, a_u.data(), a_u.size(), statistics));
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    ns.push_back(seconds * 1e9 / (static_cast<double>(passes) * static_cast<double>(steps)));
  }
  TimingResult out;
  out.repetitions = timing.repetitions;
  out.min_ns = *std::min_element(ns.begin(), ns.end());
  out.max_ns = *std::max_element(ns.begin(), ns.end());
  std::sort(ns.begin(), ns.end());
  const std::size_t mid = ns.size() / 2;
  out.median_ns = ns.size() % 2 == 1 ? ns[mid] : 0.5 * (ns[mid - 1] + ns[mid]);
  return out;
}

// A run's trace (untimed, in double whatever the scalar), for the comparison with the reference.
struct RunTrace {
  std::vector<double> x_r_m, a_x_m_per_s2;
  double transmissibility = 0.0;
  double stick_probability = 0.0;
  bool has_stick_state = false;  // sticking laws report p; the others have no stuck state
  std::uint64_t events = 0;
  bool finite = true;
};

template <typename Model, typename T>
RunTrace trace_stream(Model& model, const std::vector<T>& a_u, bool has_stick_state) {
  RunTrace trace;
  trace.has_stick_state = has_stick_state;
  trace.x_r_m.resize(a_u.size());
  trace.a_x_m_per_s2.resize(a_u.size());
  RunningStatistics<T> statistics;
  model.reset(T(0), T(0), a_u[0]);
  const StepOutput<T> first = model.current();
  statistics.add_sample(a_u[0], first.a_x_m_per_s2);
  trace.x_r_m[0] = static_cast<double>(first.x_r_m);
  trace.a_x_m_per_s2[0] = static_cast<double>(first.a_x_m_per_s2);
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<T> out = model.step(a_u[n]);
    statistics.add_sample(a_u[n], out.a_x_m_per_s2);
    statistics.add_step(out.stuck_fraction);
    trace.events += out.events;
    trace.x_r_m[n] = static_cast<double>(out.x_r_m);
    trace.a_x_m_per_s2[n] = static_cast<double>(out.a_x_m_per_s2);
    if (!std::isfinite(trace.x_r_m[n]) || !std::isfinite(trace.a_x_m_per_s2[n]))
      trace.finite = false;
  }
  trace.transmissibility = statistics.transmissibility();
  trace.stick_probability = statistics.stick_probability();
  if (!std::isfinite(trace.transmissibility)) trace.finite = false;
  return trace;
}

}  // namespace stickslip::tradeoff
