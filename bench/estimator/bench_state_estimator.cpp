// ns/sample of the state estimator's step (observer/state_estimator.hpp) on the validation
// scenario (tests/core/estimator_scenario.hpp: floor RMS 0.6 m/s^2, seed 1, 100 s at 1 kHz), for
// float and double and each set of sensors, and beside it the plain step of the seat model
// (Oscillator, stick-slip, exact integrator) on the same floor signal, so that the ratio of the two
// comes from one run on one machine state. The scenario's samples are made once, outside the
// timed loop; the loop is the estimator (or the step) alone.
//
//   stickslip_bench_state_estimator --benchmark_repetitions=5
//   --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

#include "core/estimator_scenario.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

using namespace stickslip;
using namespace stickslip::test;

struct Inputs {
  std::vector<double> a_u, a_x, x_r;
};

const Inputs& inputs() {
  static Inputs in;
  if (in.a_u.empty()) {
    EstimatorScenario sc;
    sc.floor_rms_m_per_s2 = 0.6;
    for (const ScenarioSample& s : make_scenario(sc)) {
      in.a_u.push_back(s.a_u);
      in.a_x.push_back(s.a_x);
      in.x_r.push_back(s.x_r_measured);
    }
  }
  return in;
}

template <typename T>
void estimator_stream(benchmark::State& state, Sensors sensors) {
  const Inputs& in = inputs();
  const std::size_t count = in.a_u.size();
  std::vector<T> a_u(count), a_x(count), x_r(count);
  for (std::size_t n = 0; n < count; ++n) {
    a_u[n] = T(in.a_u[n]);
    a_x[n] = sensors == Sensors::travel_only ? StateEstimator<T>::not_measured() : T(in.a_x[n]);
    x_r[n] =
        sensors == Sensors::acceleration_only ? StateEstimator<T>::not_measured() : T(in.x_r[n]);
  }
  static StateEstimator<T> estimator;
  EstimatorScenario sc;
  if (!estimator.configure(estimator_params(sc)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  for (auto _ : state) {
    estimator.reset(a_u[0]);
    T sum = T(0);
    for (std::size_t n = 1; n < count; ++n) {
      sum += estimator.step(a_u[n], a_x[n], x_r[n]).v_r_m_per_s;
    }
    benchmark::DoNotOptimize(sum);
  }
  const double samples = double(state.iterations()) * double(count - 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(samples));
  state.counters["time_per_sample"] =
      benchmark::Counter(samples, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The model the estimator corrects, stepped open loop: the cost the estimator is compared with.
template <typename T>
void plain_step(benchmark::State& state) {
  const Inputs& in = inputs();
  const std::size_t count = in.a_u.size();
  std::vector<T> a_u(count);
  for (std::size_t n = 0; n < count; ++n) a_u[n] = T(in.a_u[n]);
  const EstimatorScenario sc;
  OscillatorParams params;
  params.mass_kg = sc.mass_kg;
  params.stiffness_n_per_m = sc.stiffness_n_per_m;
  params.damping_ns_per_m = sc.damping_ns_per_m;
  params.kinetic_friction_n = sc.kinetic_friction_n;
  params.static_friction_n = sc.static_friction_n;
  params.dt_s = sc.dt_s;
  static Oscillator<T, CoulombStickSlip> oscillator;
  if (!oscillator.configure(params).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  for (auto _ : state) {
    oscillator.reset(T(0), T(0), a_u[0]);
    T sum = T(0);
    for (std::size_t n = 1; n < count; ++n) sum += oscillator.step(a_u[n]).v_r_m_per_s;
    benchmark::DoNotOptimize(sum);
  }
  const double samples = double(state.iterations()) * double(count - 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(samples));
  state.counters["time_per_sample"] =
      benchmark::Counter(samples, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void double_stream(benchmark::State& state, Sensors sensors) {
  estimator_stream<double>(state, sensors);
}
void float_stream(benchmark::State& state, Sensors sensors) {
  estimator_stream<float>(state, sensors);
}

BENCHMARK_CAPTURE(double_stream, ax_and_travel, Sensors::acceleration_and_travel)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_stream, ax_and_travel, Sensors::acceleration_and_travel)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(double_stream, ax_only, Sensors::acceleration_only)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(double_stream, travel_only, Sensors::travel_only)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_stream, ax_only, Sensors::acceleration_only)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_stream, travel_only, Sensors::travel_only)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(plain_step, double)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(plain_step, float)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
