// ns/sample of the streaming loop the host runs (oscillator step + RunningStatistics, no I/O) for
// every friction model x integrator, float and double, on generated cab-floor scenes at dt = 1 ms.
//
//   stickslip_bench_step --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//   stickslip_bench_step --benchmark_filter='stream/double/stick-slip/exact/'
//
// Names: stream/<scalar>/<model>/<integrator>/<scene kind>/F<friction N>; and for sweeps
// batch/<scalar>/N<lanes>/<inputs> (StickSlipBatch) against singles/<scalar>/N<lanes>/<inputs>
// (the same seats one after another, each over the whole scene) and
// interleaved/<scalar>/N<lanes>/<inputs> (the same seats as an array of single oscillators stepped
// together sample by sample). items_per_second counts oscillator samples; time_per_sample is in
// seconds (the console shows it with its prefix, e.g. "5.2ns"); the other counters give the
// scene's figures so that a harness can check it measured the scene it meant (K, T_ax, p, events
// per 1000 steps). The machine is shared: use repetitions, medians and
// --benchmark_enable_random_interleaving=true.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/friction/laws.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/batch_statistics.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/batch.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

using namespace stickslip;

constexpr double kDtS = 1e-3;
constexpr double kDurationS = 120.0;
constexpr double kRmsMPerS2 = 0.35;
// F_fk = F_fs: K = 1.31 (sticks about 3/4 of the time) and K = 0.44 (transition).
constexpr double kFrictionN[] = {45.0, 15.0};

// The scene's input, generated once per kind and scalar type (outside every timed loop).
template <typename T>
const std::vector<T>& scene_input(host::SignalKind kind) {
  static std::vector<T> cache[2];
  std::vector<T>& input = cache[kind == host::SignalKind::lorry ? 1 : 0];
  if (input.empty()) {
    host::GeneratorSpec spec;
    spec.kind = kind;
    spec.rms_m_per_s2 = kRmsMPerS2;
    spec.duration_s = kDurationS;
    spec.dt_s = kDtS;
    spec.seed = 1;
    const std::vector<double> signal = host::generate_signal(spec);
    input.assign(signal.begin(), signal.end());
  }
  return input;
}

// The reference seat of the README: m = 88.4 kg, k = 11.5 kN/m, b = 504 N s/m.
OscillatorParams scene_params(FrictionModel model, Integrator integrator, double friction_n) {
  OscillatorParams p;
  p.model = model;
  p.integrator = integrator;
  p.kinetic_friction_n = friction_n;
  p.static_friction_n = friction_n;
  p.dt_s = kDtS;
  return p;
}

// One pass of the loop of host::simulate_signal without the trace: what one oscillator costs per
// sample. Not inlined so that a profiler can collect exactly this (valgrind --toggle-collect).
// The statistics are a local object during the loop, as in simulate_signal: reached through a
// reference, their sums would go through memory every sample (the step's out-of-line event path
// might see them), a loop-carried store-to-load dependency worth about 1 ns per sample.
template <typename T, typename Law>
[[gnu::noinline]] std::uint64_t run_stream(Oscillator<T, Law>& seat, RunningStatistics<T>& result,
                                           const T* a_u, std::size_t count) {
  std::uint64_t events = 0;
  RunningStatistics<T> stats;
  seat.reset(T(0), T(0), a_u[0]);
  stats.reset();
  stats.add_sample(a_u[0], seat.current().a_x_m_per_s2);
  for (std::size_t n = 1; n < count; ++n) {
    const StepOutput<T> out = seat.step(a_u[n]);
    stats.add_sample(a_u[n], out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    events += out.events;
  }
  result = stats;
  return events;
}

template <typename T, typename Law>
void stream(benchmark::State& state, OscillatorParams params, host::SignalKind kind) {
  const std::vector<T>& input = scene_input<T>(kind);
  Oscillator<T, Law> seat;
  const ConfigResult configured = seat.configure(params);
  if (!configured.ok()) {
    state.SkipWithError(configured.message.c_str());
    return;
  }
  RunningStatistics<T> stats;
  std::uint64_t events = 0;
  for (auto _ : state) {
    events = run_stream(seat, stats, input.data(), input.size());
    benchmark::DoNotOptimize(stats);
    benchmark::DoNotOptimize(events);
    benchmark::ClobberMemory();
  }
  const auto steps = static_cast<double>(input.size() - 1);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(input.size() - 1));
  state.counters["time_per_sample"] = benchmark::Counter(
      steps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert,
      benchmark::Counter::kIs1000);
  state.counters["K"] = den_hartog_factor(params.kinetic_friction_n, params.mass_kg, stats.rms_u());
  state.counters["T_ax"] = stats.transmissibility();
  state.counters["p_stick"] = stats.stick_probability();
  state.counters["events_per_1k"] = 1000.0 * static_cast<double>(events) / steps;
}

template <typename T>
void register_stream(const char* scalar) {
  const Integrator integrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                    Integrator::exact};
  const host::SignalKind kinds[] = {host::SignalKind::lorry, host::SignalKind::wideband};
  const FrictionModel models[] = {FrictionModel::linear, FrictionModel::signum,
                                  FrictionModel::smooth, FrictionModel::stick_slip,
                                  FrictionModel::stribeck};
  for (FrictionModel model : models) {
    for (Integrator integrator : integrators) {
      for (host::SignalKind kind : kinds) {
        for (double friction_n : kFrictionN) {
          if (model == FrictionModel::linear && friction_n != kFrictionN[0]) continue;
          char name[160];
          std::snprintf(name, sizeof name, "stream/%s/%s/%s/%s/F%g", scalar, model_name(model),
                        integrator_name(integrator), host::signal_kind_name(kind), friction_n);
          const OscillatorParams params = scene_params(model, integrator, friction_n);
          benchmark::internal::Benchmark* b = nullptr;
          switch (model) {
            case FrictionModel::linear:
              b = benchmark::RegisterBenchmark(name, stream<T, NoFriction>, params, kind);
              break;
            case FrictionModel::signum:
              b = benchmark::RegisterBenchmark(name, stream<T, SignumFriction>, params, kind);
              break;
            case FrictionModel::smooth:  // tanh, the default smoothing law
              b = benchmark::RegisterBenchmark(name, stream<T, SmoothFriction<SmoothingLaw::tanh>>,
                                               params, kind);
              break;
            case FrictionModel::stick_slip:
              b = benchmark::RegisterBenchmark(name, stream<T, CoulombStickSlip>, params, kind);
              break;
            case FrictionModel::stribeck:
              b = benchmark::RegisterBenchmark(name, stream<T, StribeckStickSlip>, params, kind);
              break;
          }
          b->Unit(benchmark::kMillisecond);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Batch: a sweep of N stick-slip seats (exact integrator) over F_fk = F_fs from 15 N to 45 N
// (K = 0.44 ... 1.31), against the same N seats run one after another. Inputs: "shared" (every
// lane on the lorry scene) or "own" (lane i on the lorry scene delayed by i * 7.5 s, stored
// interleaved, sample-major, as a sweep over recordings would hold them).

OscillatorParams sweep_params(std::size_t lane, std::size_t lanes) {
  const double share = lanes > 1 ? static_cast<double>(lane) / static_cast<double>(lanes - 1) : 0.0;
  return scene_params(FrictionModel::stick_slip, Integrator::exact, 15.0 + 30.0 * share);
}

// Lane i's input at sample n, and the interleaved buffer [n * lanes + i].
template <typename T>
std::vector<T> interleaved_inputs(std::size_t lanes, bool own) {
  const std::vector<T>& base = scene_input<T>(host::SignalKind::lorry);
  const std::size_t count = base.size();
  std::vector<T> out(count * lanes);
  for (std::size_t n = 0; n < count; ++n) {
    for (std::size_t i = 0; i < lanes; ++i) {
      const std::size_t delay = own ? i * 7500 : 0;
      out[n * lanes + i] = base[(n + delay) % count];
    }
  }
  return out;
}

// The counters every batch/singles/interleaved benchmark reports for its lane-steps.
void set_lane_counters(benchmark::State& state, std::size_t lane_steps, std::uint64_t events,
                       double p_stick_lane0) {
  const auto samples = static_cast<double>(lane_steps);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(lane_steps));
  state.counters["time_per_sample"] = benchmark::Counter(
      samples, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["events_per_1k"] = 1000.0 * static_cast<double>(events) / samples;
  // Per iteration (not a rate): lets an instruction count of one iteration be divided out.
  state.counters["lane_steps"] = samples;
  state.counters["p_stick_lane0"] = p_stick_lane0;
}

template <typename T, std::size_t N>
[[gnu::noinline]] std::uint64_t run_batch(StickSlipBatch<T, N>& batch, BatchStatistics<T, N>& stats,
                                          const T* a_u, std::size_t count) {
  std::uint64_t events = 0;
  T a_x0[N];
  for (std::size_t i = 0; i < N; ++i) {
    batch.reset(i, T(0), T(0), a_u[i]);
    a_x0[i] = batch.lane(i).current().a_x_m_per_s2;
  }
  stats.reset();
  stats.add_sample(a_u, a_x0);
  for (std::size_t n = 1; n < count; ++n) {
    const T(&sample)[N] = *reinterpret_cast<const T(*)[N]>(a_u + n * N);
    batch.step(sample);
    stats.add_sample(sample, batch.a_x_array());
    stats.add_step(batch.stuck_fraction_array());
    unsigned step_events = 0;
    for (std::size_t i = 0; i < N; ++i) step_events += batch.events(i);
    events += step_events;
  }
  return events;
}

template <typename T, std::size_t N>
void batch_bench(benchmark::State& state, bool own_inputs) {
  const std::vector<T> input = interleaved_inputs<T>(N, own_inputs);
  const std::size_t count = input.size() / N;
  static StickSlipBatch<T, N> batch;  // static: kept off the stack (about 2.3 kB per lane)
  for (std::size_t i = 0; i < N; ++i) {
    const ConfigResult configured = batch.configure(i, sweep_params(i, N));
    if (!configured.ok()) {
      state.SkipWithError(configured.message.c_str());
      return;
    }
  }
  BatchStatistics<T, N> stats;
  std::uint64_t events = 0;
  for (auto _ : state) {
    events = run_batch(batch, stats, input.data(), count);
    benchmark::DoNotOptimize(stats);
    benchmark::DoNotOptimize(events);
    benchmark::ClobberMemory();
  }
  set_lane_counters(state, (count - 1) * N, events, stats.lane(0).stick_probability());
}

// The same N seats and inputs, one single oscillator after another (each with its statistics).
template <typename T, std::size_t N>
void singles_bench(benchmark::State& state, bool own_inputs) {
  const std::vector<T> interleaved = interleaved_inputs<T>(N, own_inputs);
  const std::size_t count = interleaved.size() / N;
  std::vector<std::vector<T>> inputs(N, std::vector<T>(count));
  for (std::size_t n = 0; n < count; ++n)
    for (std::size_t i = 0; i < N; ++i) inputs[i][n] = interleaved[n * N + i];
  static Oscillator<T, CoulombStickSlip> seats[N];
  for (std::size_t i = 0; i < N; ++i) {
    const ConfigResult configured = seats[i].configure(sweep_params(i, N));
    if (!configured.ok()) {
      state.SkipWithError(configured.message.c_str());
      return;
    }
  }
  RunningStatistics<T> stats[N];
  std::uint64_t events = 0;
  for (auto _ : state) {
    events = 0;
    for (std::size_t i = 0; i < N; ++i) {
      events += run_stream(seats[i], stats[i], inputs[i].data(), count);
      benchmark::DoNotOptimize(stats[i]);
    }
    benchmark::DoNotOptimize(events);
    benchmark::ClobberMemory();
  }
  set_lane_counters(state, (count - 1) * N, events, stats[0].stick_probability());
}

// The same N seats stepped together sample by sample without the batch (an array of single
// oscillators: independent dependency chains side by side, scalar code).
template <typename T, std::size_t N>
[[gnu::noinline]] std::uint64_t run_interleaved(Oscillator<T, CoulombStickSlip> (&seats)[N],
                                                RunningStatistics<T> (&stats)[N], const T* a_u,
                                                std::size_t count) {
  std::uint64_t events = 0;
  for (std::size_t i = 0; i < N; ++i) {
    seats[i].reset(T(0), T(0), a_u[i]);
    stats[i].reset();
    stats[i].add_sample(a_u[i], seats[i].current().a_x_m_per_s2);
  }
  for (std::size_t n = 1; n < count; ++n) {
    for (std::size_t i = 0; i < N; ++i) {
      const T a = a_u[n * N + i];
      const StepOutput<T> out = seats[i].step(a);
      stats[i].add_sample(a, out.a_x_m_per_s2);
      stats[i].add_step(out.stuck_fraction);
      events += out.events;
    }
  }
  return events;
}

template <typename T, std::size_t N>
void interleaved_bench(benchmark::State& state, bool own_inputs) {
  const std::vector<T> input = interleaved_inputs<T>(N, own_inputs);
  const std::size_t count = input.size() / N;
  static Oscillator<T, CoulombStickSlip> seats[N];
  for (std::size_t i = 0; i < N; ++i) {
    const ConfigResult configured = seats[i].configure(sweep_params(i, N));
    if (!configured.ok()) {
      state.SkipWithError(configured.message.c_str());
      return;
    }
  }
  RunningStatistics<T> stats[N];
  std::uint64_t events = 0;
  for (auto _ : state) {
    events = run_interleaved(seats, stats, input.data(), count);
    benchmark::DoNotOptimize(stats);
    benchmark::DoNotOptimize(events);
    benchmark::ClobberMemory();
  }
  set_lane_counters(state, (count - 1) * N, events, stats[0].stick_probability());
}

template <typename T, std::size_t N>
void register_batch(const char* scalar) {
  for (bool own : {false, true}) {
    char name[120];
    const char* inputs = own ? "own-inputs" : "shared-input";
    std::snprintf(name, sizeof name, "batch/%s/N%zu/%s", scalar, N, inputs);
    benchmark::RegisterBenchmark(name, batch_bench<T, N>, own)->Unit(benchmark::kMillisecond);
    std::snprintf(name, sizeof name, "singles/%s/N%zu/%s", scalar, N, inputs);
    benchmark::RegisterBenchmark(name, singles_bench<T, N>, own)->Unit(benchmark::kMillisecond);
    std::snprintf(name, sizeof name, "interleaved/%s/N%zu/%s", scalar, N, inputs);
    benchmark::RegisterBenchmark(name, interleaved_bench<T, N>, own)->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_stream<double>("double");
  register_stream<float>("float");
  register_batch<double, 4>("double");
  register_batch<double, 8>("double");
  register_batch<double, 16>("double");
  register_batch<float, 8>("float");
  register_batch<float, 16>("float");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
