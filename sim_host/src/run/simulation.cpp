#include "stickslip/host/run/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <type_traits>
#include <utility>

#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/host/run/fixed_dispatch.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/ride_comfort.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/scaled_end_stops.hpp"
#include "stickslip/models/scaled_oscillator.hpp"
#include "stickslip/models/scene.hpp"

namespace stickslip::host {

const char* scalar_name(ScalarType scalar) noexcept {
  switch (scalar) {
    case ScalarType::float32:
      return "float";
    case ScalarType::fixed:
      return "fixed";
    case ScalarType::fixed32:
      return "fixed32";
    case ScalarType::float64:
    default:
      return "double";
  }
}

bool parse_scalar(const std::string& name, ScalarType& out) noexcept {
  if (name == "double") {
    out = ScalarType::float64;
    return true;
  }
  if (name == "float") {
    out = ScalarType::float32;
    return true;
  }
  if (name == "fixed") {
    out = ScalarType::fixed;
    return true;
  }
  if (name == "fixed32") {
    out = ScalarType::fixed32;
    return true;
  }
  return false;
}

namespace {

int repetitions_for(const SimulationSetup& setup, std::size_t count) {
  return setup.repetitions > 0 ? setup.repetitions : (count - 1 > kManySteps ? 3 : 5);
}

// The figures a timed run adds to summarise_run()'s: dt, K (which describes the scene, its
// friction against its excitation, whichever model runs it), the median time per sample.
void add_run_figures(SimulationSummary& summary, const SimulationSetup& setup,
                     std::vector<double>& seconds, std::size_t count) {
  const auto repetitions = static_cast<int>(seconds.size());
  std::nth_element(seconds.begin(), seconds.begin() + repetitions / 2, seconds.end());
  summary.dt_s = setup.params.dt_s;
  summary.den_hartog_k =
      den_hartog_factor(setup.params.kinetic_friction_n, setup.params.mass_kg, summary.rms_u);
  summary.ns_per_sample =
      seconds[static_cast<std::size_t>(repetitions / 2)] * 1e9 / static_cast<double>(count - 1);
  summary.repetitions = repetitions;
}

// `--integrator reference`: solve_reference() timed like the core's loop (median of the runs),
// its trace moved into `trace`, the statistics from the trace.
SimulationSummary simulate_reference(const SimulationSetup& setup, const std::vector<double>& a_u,
                                     SimulationTrace<double>& trace) {
  const std::size_t count = a_u.size();
  const int repetitions = repetitions_for(setup, count);
  ReferenceTrace result;
  std::vector<double> seconds;
  seconds.reserve(static_cast<std::size_t>(repetitions));
  for (int repetition = 0; repetition < repetitions; ++repetition) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<double> no_force;
    const std::vector<double>& force =
        setup.actuator_force_n == nullptr ? no_force : *setup.actuator_force_n;
    if (setup.effects & kEndStops) {
      result = solve_reference_actuated(setup.params, setup.stops, a_u, force, setup.x0_m,
                                        setup.v0_m_per_s);
    } else {
      result =
          setup.actuator_force_n == nullptr
              ? solve_reference(setup.params, a_u, setup.x0_m, setup.v0_m_per_s)
              : solve_reference_actuated(setup.params, a_u, force, setup.x0_m, setup.v0_m_per_s);
    }
    const auto stop = std::chrono::steady_clock::now();
    seconds.push_back(std::chrono::duration<double>(stop - start).count());
  }
  std::nth_element(seconds.begin(), seconds.begin() + repetitions / 2, seconds.end());

  RunningStatistics<double> statistics;
  statistics.reset();
  for (std::size_t n = 0; n < count; ++n) statistics.add_sample(a_u[n], result.a_x_m_per_s2[n]);
  SimulationSummary summary;
  summary.samples = statistics.samples();
  summary.steps = count - 1;
  summary.dt_s = setup.params.dt_s;
  summary.rms_u = statistics.rms_u();
  summary.rms_x = statistics.rms_x();
  summary.transmissibility = statistics.transmissibility();
  summary.stick_probability =
      result.stuck_time_s / (static_cast<double>(count - 1) * setup.params.dt_s);
  summary.den_hartog_k =
      den_hartog_factor(setup.params.kinetic_friction_n, setup.params.mass_kg, summary.rms_u);
  summary.ns_per_sample =
      seconds[static_cast<std::size_t>(repetitions / 2)] * 1e9 / static_cast<double>(count - 1);
  summary.repetitions = repetitions;
  summary.events = result.events;
  if (setup.effects & kEndStops) {
    summary.end_stops = true;
    summary.end_stop_contacts = result.contacts;
  }
  trace.x_r_m = std::move(result.x_r_m);
  trace.v_r_m_per_s = std::move(result.v_r_m_per_s);
  trace.a_x_m_per_s2 = std::move(result.a_x_m_per_s2);
  trace.friction_n = std::move(result.friction_n);
  trace.stuck = std::move(result.stuck);
  return summary;
}

}  // namespace

namespace {

// What both fixed-point runs check first: the input, the solver, and the models fixed point does
// not offer (named by the core's own check); then the trace's rows.
template <typename T>
void prepare_fixed_point_run(const SimulationSetup& setup, std::size_t count,
                             SimulationTrace<double>& trace) {
  if (count < 2) throw HostError("simulate needs at least 2 samples");
  if (setup.reference) {
    throw UsageError("--scalar: the reference integrator runs in double only; use --scalar double");
  }
  if (setup.params.model == FrictionModel::stribeck ||
      (setup.params.model == FrictionModel::smooth &&
       setup.params.smoothing != SmoothingLaw::rational)) {
    DiscreteModel model;
    ConfigResult refused = discretise(setup.params, model);
    if (refused.ok()) {
      refused = check_fixed_point_scene(setup.params, model, T::kIntegerBits, T::kFractionBits,
                                        ScalarTraits<T>::kEventTickLevel, ParameterUnits::si);
    }
    throw ConfigurationError(refused.message.c_str());
  }
  trace.resize(count);
}

// The timed loop of a configured fixed-point oscillator whose values are in `units` (all 1 for
// Q23.40, which runs in SI; the scene units of a ScaledOscillator for Q7.24). The input is
// converted once per sample, as an ECU converts its input: a sample beyond the format saturates
// and the step it feeds counts it. The trace and the statistics hold the outputs in SI.
template <typename T, typename Model>
SimulationSummary run_fixed_point(const SimulationSetup& setup, const std::vector<double>& a_u,
                                  SimulationTrace<double>& trace, Model& oscillator,
                                  const SceneUnits& units) {
  const std::size_t count = a_u.size();
  const int repetitions = repetitions_for(setup, count);
  const double acceleration_unit = units.acceleration_m_per_s2();
  const auto input = [&](double a_m_per_s2) { return T(a_m_per_s2 / acceleration_unit); };
  const std::vector<double>* force = setup.actuator_force_n;
  const auto force_at = [&](std::size_t n) { return T((*force)[n] / units.force_n()); };
  const T x0(setup.x0_m / units.length_m), v0(setup.v0_m_per_s / units.velocity_m_per_s());
  RunningStatistics<double> statistics;
  std::uint64_t events = 0, saturated_steps = 0;
  const auto store = [&](std::size_t n, const StepOutput<T>& out) {
    trace.x_r_m[n] = out.x_r_m.to_double() * units.length_m;
    trace.v_r_m_per_s[n] = out.v_r_m_per_s.to_double() * units.velocity_m_per_s();
    trace.a_x_m_per_s2[n] = out.a_x_m_per_s2.to_double() * acceleration_unit;
    trace.friction_n[n] = out.friction_n.to_double() * units.force_n();
    trace.stuck[n] = out.stuck ? 1 : 0;
  };
  std::vector<double> seconds;
  seconds.reserve(static_cast<std::size_t>(repetitions));
  for (int repetition = 0; repetition < repetitions; ++repetition) {
    const auto start = std::chrono::steady_clock::now();
    // (The initial state's conversions: a value beyond the format is counted as a saturated
    // step of its own.)
    const T a_u0 = input(a_u[0]);
    const T f_a0 = force != nullptr ? force_at(0) : T(0);
    const bool start_saturated = take_fixed_point_saturation();
    if (force != nullptr) {
      oscillator.reset(x0, v0, a_u0, f_a0);
      store(0, oscillator.current_with_force(f_a0));
    } else {
      oscillator.reset(x0, v0, a_u0);
      store(0, oscillator.current());
    }
    statistics.reset();
    events = 0;
    statistics.add_sample(a_u0.to_double() * acceleration_unit, trace.a_x_m_per_s2[0]);
    for (std::size_t n = 1; n < count; ++n) {
      const T a_u_n = input(a_u[n]);
      const StepOutput<T> out =
          force != nullptr ? oscillator.step(a_u_n, force_at(n)) : oscillator.step(a_u_n);
      store(n, out);
      statistics.add_sample(a_u_n.to_double() * acceleration_unit, trace.a_x_m_per_s2[n]);
      statistics.add_step(out.stuck_fraction.to_double());
      events += out.events;
    }
    const auto stop = std::chrono::steady_clock::now();
    seconds.push_back(std::chrono::duration<double>(stop - start).count());
    saturated_steps = oscillator.saturated_steps() + (start_saturated ? 1u : 0u);
  }
  SimulationSummary summary;
  summarise_run(summary, statistics, oscillator, events);
  add_run_figures(summary, setup, seconds, count);
  summary.saturated_steps = saturated_steps;
  return summary;
}

template <typename Law>
using Fixed32Seat = ScaledOscillator<Fixed32, Law>;

// The models whose step takes an actuator force (the oscillator, the end-stop model).
template <typename Model, typename T, typename = void>
struct TakesActuatorForce : std::false_type {};
template <typename Model, typename T>
struct TakesActuatorForce<
    Model, T,
    std::void_t<decltype(std::declval<Model&>().step(std::declval<T>(), std::declval<T>()))>>
    : std::true_type {};

// The loop of simulate_signal() with the actuator force of every sample; untimed work apart, the
// same steps as Oscillator::step(a_u, f_a) in a controller's loop.
template <typename T, typename Model>
void run_actuated(Model& oscillator, const SimulationSetup& setup, const T* input,
                  const std::vector<T>& force, std::size_t count, RunningStatistics<T>& statistics,
                  std::uint64_t& events, SimulationTrace<T>& trace) {
  oscillator.reset(static_cast<T>(setup.x0_m), static_cast<T>(setup.v0_m_per_s), input[0],
                   force[0]);
  statistics.reset();
  events = 0;
  const StepOutput<T> initial = oscillator.current_with_force(force[0]);
  trace.store(0, initial);
  statistics.add_sample(input[0], initial.a_x_m_per_s2);
  for (std::size_t n = 1; n < count; ++n) {
    const StepOutput<T> out = oscillator.step(input[n], force[n]);
    trace.store(n, out);
    statistics.add_sample(input[n], out.a_x_m_per_s2);
    statistics.add_step(out.stuck_fraction);
    events += out.events;
  }
}

}  // namespace

SimulationSummary simulate_signal_fixed(const SimulationSetup& setup,
                                        const std::vector<double>& a_u,
                                        SimulationTrace<double>& trace) {
  prepare_fixed_point_run<Fixed>(setup, a_u.size(), trace);
  // With end stops, the end-stop model's configure() checks the seat free and in contact.
  const SceneParams scene{setup.effects, setup.params, setup.stops};
  return with_fixed_scene_model(scene, [&](auto& model) {
    const ConfigResult configured = configure_for_scene(model, scene);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    return run_fixed_point<Fixed>(setup, a_u, trace, model, SceneUnits{});  // SI
  });
}

SimulationSummary simulate_signal_fixed32(const SimulationSetup& setup,
                                          const std::vector<double>& a_u,
                                          SimulationTrace<double>& trace) {
  prepare_fixed_point_run<Fixed32>(setup, a_u.size(), trace);
  if (setup.effects & kEndStops) {
    // The end-stop model in scene units: no friction, or Coulomb stick-slip, whose configure()
    // refuses any other model by name (as Q23.40's).
    const auto run = [&](auto& seat) {
      const ConfigResult configured = seat.configure(setup.params, setup.stops);
      if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
      return run_fixed_point<Fixed32>(setup, a_u, trace, seat.oscillator(), seat.units());
    };
    if (setup.params.model == FrictionModel::linear) {
      ScaledEndStopOscillator<Fixed32, NoFriction> seat;
      return run(seat);
    }
    ScaledEndStopOscillator<Fixed32, CoulombStickSlip> seat;
    return run(seat);
  }
  return with_fixed_law<Fixed32Seat>(setup.params, [&](auto& seat) {
    const ConfigResult configured = seat.configure(setup.params);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
    return run_fixed_point<Fixed32>(setup, a_u, trace, seat.oscillator(), seat.units());
  });
}

template <typename T>
SimulationSummary simulate_signal(const SimulationSetup& setup, const std::vector<T>& a_u,
                                  SimulationTrace<T>& trace) {
  const std::size_t count = a_u.size();
  if (count < 2) throw HostError("simulate needs at least 2 samples");
  if (setup.reference) {
    if constexpr (std::is_same_v<T, double>) {
      return simulate_reference(setup, a_u, trace);
    } else {
      throw UsageError(
          "--scalar: the reference integrator runs in double only (long double inside); use "
          "--scalar double");
    }
  }
  trace.resize(count);
  const int repetitions = repetitions_for(setup, count);
  const T x0 = static_cast<T>(setup.x0_m);
  const T v0 = static_cast<T>(setup.v0_m_per_s);

  // The model is chosen once, here, outside the sample loop: exactly the scene's effects.
  const SceneParams scene{setup.effects, setup.params, setup.stops};
  return with_scene_model<T>(scene, [&](auto& oscillator) {
    const ConfigResult configured = configure_for_scene(oscillator, scene);
    if (!configured.ok()) throw ConfigurationError(configured.message.c_str());

    RunningStatistics<T> statistics;
    std::uint64_t events = 0;
    const T* input = a_u.data();
    T* x_r = trace.x_r_m.data();
    T* v_r = trace.v_r_m_per_s.data();
    T* a_x = trace.a_x_m_per_s2.data();
    T* friction = trace.friction_n.data();
    std::uint8_t* stuck = trace.stuck.data();
    const auto store = [&](std::size_t n, const StepOutput<T>& out) {
      x_r[n] = out.x_r_m;
      v_r[n] = out.v_r_m_per_s;
      a_x[n] = out.a_x_m_per_s2;
      friction[n] = out.friction_n;
      stuck[n] = out.stuck ? 1 : 0;
    };

    std::vector<double> seconds;
    seconds.reserve(static_cast<std::size_t>(repetitions));
    if (setup.actuator_force_n != nullptr) {
      using Model = std::remove_reference_t<decltype(oscillator)>;
      if constexpr (TakesActuatorForce<Model, T>::value) {
        const std::vector<T> force(setup.actuator_force_n->begin(), setup.actuator_force_n->end());
        for (int repetition = 0; repetition < repetitions; ++repetition) {
          const auto start = std::chrono::steady_clock::now();
          run_actuated(oscillator, setup, input, force, count, statistics, events, trace);
          const auto stop = std::chrono::steady_clock::now();
          seconds.push_back(std::chrono::duration<double>(stop - start).count());
        }
      } else {
        throw UsageError("f_a: this seat model takes no actuator force");
      }
    }
    const bool passive = setup.actuator_force_n == nullptr;
    for (int repetition = 0; passive && repetition < repetitions; ++repetition) {
      const auto start = std::chrono::steady_clock::now();
      oscillator.reset(x0, v0, input[0]);
      statistics.reset();
      events = 0;
      const StepOutput<T> initial = oscillator.current();
      store(0, initial);
      statistics.add_sample(input[0], initial.a_x_m_per_s2);
      for (std::size_t n = 1; n < count; ++n) {
        const StepOutput<T> out = oscillator.step(input[n]);
        store(n, out);
        statistics.add_sample(input[n], out.a_x_m_per_s2);
        statistics.add_step(out.stuck_fraction);
        events += out.events;
      }
      const auto stop = std::chrono::steady_clock::now();
      seconds.push_back(std::chrono::duration<double>(stop - start).count());
    }
    SimulationSummary summary;
    summarise_run(summary, statistics, oscillator, events);
    add_run_figures(summary, setup, seconds, count);
    return summary;
  });
}

template <typename T>
void add_ride_comfort(SimulationSummary& summary, const std::vector<double>& a_u,
                      const std::vector<T>& a_x, double dt_s) {
  RideComfort<double> comfort;
  const ConfigResult configured = comfort.configure(ComfortWeighting::wk, 1.0 / dt_s);
  if (!configured.ok()) throw ConfigurationError(configured.message.c_str());
  const std::size_t count = std::min(a_u.size(), a_x.size());
  for (std::size_t n = 0; n < count; ++n) comfort.add_sample(a_u[n], static_cast<double>(a_x[n]));
  summarise_comfort(summary, comfort);
  summary.comfort = true;
}

template void add_ride_comfort<double>(SimulationSummary&, const std::vector<double>&,
                                       const std::vector<double>&, double);
template void add_ride_comfort<float>(SimulationSummary&, const std::vector<double>&,
                                      const std::vector<float>&, double);

template SimulationSummary simulate_signal<double>(const SimulationSetup&,
                                                   const std::vector<double>&,
                                                   SimulationTrace<double>&);
template SimulationSummary simulate_signal<float>(const SimulationSetup&, const std::vector<float>&,
                                                  SimulationTrace<float>&);

}  // namespace stickslip::host
