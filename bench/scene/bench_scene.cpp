// Cost per sample of each scene effect: the streaming loop (model step + RunningStatistics, no
// I/O) over the 120 s lorry-like scene at dt = 1 ms, for scenes composed with with_scene_model()
// (dispatched once, outside the loop), against a hand-written linear oscillator: the same exact
// first-order-hold map, written out by hand with nothing else in the step.
//
// Names: scene/<scalar>/<effects>; counters: time_per_sample, p_stick, contacts_per_1k.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/scene.hpp"

namespace {

using namespace stickslip;

constexpr double kDtS = 1e-3;
constexpr double kFrictionN = 30.0;  // K = 0.87 on this scene: sticks about half the time

template <typename T>
const std::vector<T>& lorry_input() {
  static std::vector<T> input;
  if (input.empty()) {
    host::GeneratorSpec spec;
    spec.kind = host::SignalKind::lorry;
    spec.rms_m_per_s2 = 0.35;
    spec.duration_s = 120.0;
    spec.dt_s = kDtS;
    spec.seed = 1;
    const std::vector<double> signal = host::generate_signal(spec);
    input.assign(signal.begin(), signal.end());
  }
  return input;
}

// The hand-written linear seat: x' = xx x + xv v + gx0 g0 + gx1 g1 (and v), g = -a_u, and the
// seat acceleration -(k x + b v)/m, with the library's contract (a non-finite input sample is
// replaced by the previous one; a non-finite state restarts from rest). Nothing else: what a
// linear scene needs.
template <typename T>
struct HandWrittenLinear {
  T xx, xv, vx, vv, gx0, gx1, gv0, gv1, k_over_m, b_over_m;
  T x = T(0), v = T(0), a_prev = T(0);
  explicit HandWrittenLinear(const OscillatorParams& p) {
    const StepMap<double> m = linear_step_map(Integrator::exact, p.stiffness_n_per_m / p.mass_kg,
                                              p.damping_ns_per_m / p.mass_kg, p.dt_s);
    xx = T(m.xx), xv = T(m.xv), vx = T(m.vx), vv = T(m.vv);
    gx0 = T(m.gx0), gx1 = T(m.gx1), gv0 = T(m.gv0), gv1 = T(m.gv1);
    k_over_m = T(p.stiffness_n_per_m / p.mass_kg);
    b_over_m = T(p.damping_ns_per_m / p.mass_kg);
  }
  T step(T a) {
    if (!std::isfinite(a)) a = a_prev;
    const T g0 = -a_prev, g1 = -a;
    const T xn = (xx * x + xv * v) + (gx0 * g0 + gx1 * g1);
    const T vn = (vx * x + vv * v) + (gv0 * g0 + gv1 * g1);
    x = xn;
    v = vn;
    a_prev = a;
    if (!(std::isfinite(x) && std::isfinite(v))) x = v = T(0);  // the contract: never NaN/Inf
    return -(k_over_m * x + b_over_m * v);
  }
};

template <typename T>
[[gnu::noinline]] void run_hand_written(HandWrittenLinear<T>& seat, RunningStatistics<T>& result,
                                        const T* a_u, std::size_t count) {
  RunningStatistics<T> stats;
  seat.x = seat.v = T(0);
  seat.a_prev = a_u[0];
  stats.add_sample(a_u[0], T(0));
  for (std::size_t n = 1; n < count; ++n) {
    stats.add_sample(a_u[n], seat.step(a_u[n]));
    stats.add_step(T(0));
  }
  result = stats;
}

template <typename T, typename Model>
[[gnu::noinline]] std::uint64_t run_model(Model& seat, RunningStatistics<T>& result, const T* a_u,
                                          std::size_t count) {
  RunningStatistics<T> stats;
  std::uint64_t events = 0;
  seat.reset(T(0), T(0), a_u[0]);
  stats.add_sample(a_u[0], a_u[0]);
  for (std::size_t n = 1; n < count; ++n) {
    const StepOutput<T> out = seat.step(a_u[n]);
    stats.add_sample(a_u[n], out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    events += out.events;
  }
  result = stats;
  return events;
}

void set_counters(benchmark::State& state, std::size_t steps, double p, double events) {
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(steps));
  state.counters["time_per_sample"] = benchmark::Counter(
      double(steps), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert,
      benchmark::Counter::kIs1000);
  state.counters["p_stick"] = p;
  state.counters["events_per_1k"] = 1000.0 * events / double(steps);
}

template <typename T>
void hand_written(benchmark::State& state) {
  const std::vector<T>& input = lorry_input<T>();
  OscillatorParams p;
  p.model = FrictionModel::linear;
  p.dt_s = kDtS;
  HandWrittenLinear<T> seat(p);
  RunningStatistics<T> stats;
  for (auto _ : state) {
    run_hand_written(seat, stats, input.data(), input.size());
    benchmark::DoNotOptimize(stats);
    benchmark::ClobberMemory();
  }
  set_counters(state, input.size() - 1, 0.0, 0.0);
}

template <typename T>
void scene(benchmark::State& state, SceneParams params) {
  const std::vector<T>& input = lorry_input<T>();
  with_scene_model<T>(params, [&](auto& seat) {
    const ConfigResult configured = configure_for_scene(seat, params);
    if (!configured.ok()) {
      state.SkipWithError(configured.message.c_str());
      return 0;
    }
    RunningStatistics<T> stats;
    std::uint64_t events = 0;
    for (auto _ : state) {
      events = run_model<T>(seat, stats, input.data(), input.size());
      benchmark::DoNotOptimize(stats);
      benchmark::ClobberMemory();
    }
    set_counters(state, input.size() - 1, stats.stick_probability(), double(events));
    return 0;
  });
}

SceneParams make_scene(unsigned effects) {
  SceneParams s;
  s.effects = effects;
  s.seat.dt_s = kDtS;
  s.seat.model = model_for_effects(effects);
  s.seat.integrator = default_integrator(s.seat.model);
  s.seat.kinetic_friction_n = (effects & kCoulomb) ? kFrictionN : 0.0;
  s.seat.static_friction_n = (effects & kStribeck) ? 1.3 * kFrictionN : s.seat.kinetic_friction_n;
  s.stops.travel_m = 0.004;  // reached now and then on this scene
  s.stops.stiffness_n_per_m = 2e5;
  s.stops.damping_ns_per_m = 2e3;
  return s;
}

template <typename T>
void register_all(const char* scalar) {
  const std::string prefix = std::string("scene/") + scalar + "/";
  benchmark::RegisterBenchmark((prefix + "hand-written-linear").c_str(), hand_written<T>)
      ->Unit(benchmark::kMillisecond);
  const struct {
    const char* name;
    unsigned effects;
  } scenes[] = {
      {"spring+damper", kSpring | kDamper},
      {"+coulomb", kSpring | kDamper | kCoulomb},
      {"+coulomb+static", kSpring | kDamper | kCoulomb | kStaticFriction},
      {"+coulomb+static+stribeck", kSpring | kDamper | kCoulomb | kStaticFriction | kStribeck},
      {"spring+damper+end-stops", kSpring | kDamper | kEndStops},
      {"+coulomb+static+end-stops", kSpring | kDamper | kCoulomb | kStaticFriction | kEndStops},
  };
  for (const auto& s : scenes) {
    benchmark::RegisterBenchmark((prefix + s.name).c_str(), scene<T>, make_scene(s.effects))
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all<double>("double");
  register_all<float>("float");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
