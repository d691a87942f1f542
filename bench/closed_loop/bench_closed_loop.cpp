// ns per sample of the closed loop (control/closed_loop.hpp): the plant's step under the held
// force, the sensors (noise added, travel quantised), the observer, the controller and the
// actuator, one ClosedLoop::step per sample; and in the same run the plant's actuated step alone
// on the same floor, so the loop's overhead is a ratio from one machine state. The floor (a
// lorry-like 60 s at 1 kHz, RMS 0.6 m/s^2) and the sensor noise are made once, outside the timed
// loop. Seat: the reference seat, stick-slip (F_fk = 40 N, F_fs = 55 N), exact integrator.
//
//   stickslip_bench_closed_loop --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "core/estimator_scenario.hpp"
#include "stickslip/control/closed_loop.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

using namespace stickslip;

constexpr double kDt = 1e-3;
constexpr std::size_t kSamples = 60001;

struct Inputs {
  std::vector<double> a_u, a_x_noise, x_r_noise;
};

const Inputs& inputs() {
  static Inputs in;
  if (in.a_u.empty()) {
    in.a_u = test::lorry_floor(1, 0.6, kSamples, kDt);
    std::mt19937_64 random(7);
    std::normal_distribution<double> normal;
    for (std::size_t n = 0; n < kSamples; ++n) {
      in.a_x_noise.push_back(0.02 * normal(random));
      in.x_r_noise.push_back(3e-5 * normal(random));
    }
  }
  return in;
}

OscillatorParams seat_params() {
  OscillatorParams p;
  p.model = FrictionModel::stick_slip;
  p.kinetic_friction_n = 40.0;
  p.static_friction_n = 55.0;
  p.dt_s = kDt;
  return p;
}

ClosedLoopParams loop_params(LoopController controller, ObserverKind observer) {
  const OscillatorParams seat = seat_params();
  ClosedLoopParams p;
  p.dt_s = kDt;
  p.controller = controller;
  p.hook.reference = HookReference::sky;
  p.hook.device = HookDevice::semi_active;
  p.observer = observer;
  p.estimator.mass_kg = seat.mass_kg;
  p.estimator.stiffness_n_per_m = seat.stiffness_n_per_m;
  p.estimator.damping_ns_per_m = seat.damping_ns_per_m;
  p.estimator.initial_kinetic_friction_n = seat.kinetic_friction_n;
  p.estimator.initial_static_friction_n = seat.static_friction_n;
  p.travel_resolution_m = 1e-4;
  return p;
}

void per_sample(benchmark::State& state) {
  const double samples = double(state.iterations()) * double(kSamples - 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(samples));
  state.counters["time_per_sample"] =
      benchmark::Counter(samples, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// One closed-loop sample: plant + sensors + observer + controller + actuator.
template <typename T>
void loop(benchmark::State& state, LoopController controller, ObserverKind observer) {
  const Inputs& in = inputs();
  std::vector<T> a_u(in.a_u.begin(), in.a_u.end());
  std::vector<T> ax_noise(in.a_x_noise.begin(), in.a_x_noise.end());
  std::vector<T> xr_noise(in.x_r_noise.begin(), in.x_r_noise.end());
  static Oscillator<T, CoulombStickSlip> seat;
  static ClosedLoop<T> closed;
  if (!seat.configure(seat_params()).ok() ||
      !closed.configure(loop_params(controller, observer)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  for (auto _ : state) {
    seat.reset(T(0), T(0), a_u[0]);
    closed.reset(a_u[0]);
    T sum = T(0);
    for (std::size_t n = 1; n < kSamples; ++n)
      sum += closed.step(seat, a_u[n], ax_noise[n], xr_noise[n]).next_force_n;
    benchmark::DoNotOptimize(sum);
  }
  per_sample(state);
}

// The plant alone, its actuated step under a force that changes every sample (the loop's force
// stands in: the previous sample's v_r times a damping), on the same floor.
template <typename T>
void plant(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<T> a_u(in.a_u.begin(), in.a_u.end());
  static Oscillator<T, CoulombStickSlip> seat;
  if (!seat.configure(seat_params()).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  for (auto _ : state) {
    seat.reset(T(0), T(0), a_u[0]);
    T force = T(0), sum = T(0);
    for (std::size_t n = 1; n < kSamples; ++n) {
      const StepOutput<T> out = seat.step(a_u[n], force);
      force = T(-1500) * out.v_r_m_per_s;
      sum += out.a_x_m_per_s2;
    }
    benchmark::DoNotOptimize(sum);
  }
  per_sample(state);
}

void double_loop(benchmark::State& state, LoopController c, ObserverKind o) {
  loop<double>(state, c, o);
}
void float_loop(benchmark::State& state, LoopController c, ObserverKind o) {
  loop<float>(state, c, o);
}

// The headline: semi-active skyhook on the state estimator's v_r, the sensors an ECU has.
BENCHMARK_CAPTURE(double_loop, skyhook_semi_estimator, LoopController::hook,
                  ObserverKind::estimator)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_loop, skyhook_semi_estimator, LoopController::hook, ObserverKind::estimator)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(double_loop, skyhook_semi_ideal, LoopController::hook, ObserverKind::ideal)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(double_loop, passive_estimator, LoopController::passive, ObserverKind::estimator)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(plant, double)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(plant, float)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
