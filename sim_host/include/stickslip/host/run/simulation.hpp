// Runs the core's oscillator over a whole recorded signal and measures it: the loop every host
// command uses (simulate, demo) so that they agree bit for bit with an in-process run.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/models/scene.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip::host {

// fixed: the core's Q23.40 fixed-point scalar (core/fixed_point.hpp); fixed32: Q7.24 in scene
// units (core/fixed_point32.hpp, models/scaled_oscillator.hpp), the Cortex-M0+ build's scalar.
enum class ScalarType : std::uint8_t { float64, float32, fixed, fixed32 };
const char* scalar_name(ScalarType scalar) noexcept;  // "double", "float", "fixed", "fixed32"
bool parse_scalar(const std::string& name, ScalarType& out) noexcept;

struct SimulationSetup {
  OscillatorParams params;  // dt_s from the signal
  double x0_m = 0.0;
  double v0_m_per_s = 0.0;
  int repetitions = 0;  // timed runs of the loop; 0: 5, or 3 above kManySteps steps
  // Run the event-driven reference solver (reference_solver.hpp, `--integrator reference`)
  // instead of the core; params.integrator is then ignored. Double only.
  bool reference = false;
  // The scene's effects (models/scene.hpp): with kEndStops the end-stop model runs, with `stops`.
  unsigned effects = kSpring | kDamper | kCoulomb | kStaticFriction | kStribeck;
  EndStopParams stops;
  // An actuator force (N) per input sample, held over the step that ends at that sample
  // (Oscillator::step(a_u, f_a)); nullptr: none, and the run is the plain step(a_u) loop.
  const std::vector<double>* actuator_force_n = nullptr;
};

inline constexpr std::uint64_t kManySteps = 2000000;

// One row per input sample; row 0 is the initial state (oscillator.current()).
template <typename T>
struct SimulationTrace {
  std::vector<T> x_r_m, v_r_m_per_s, a_x_m_per_s2, friction_n;
  std::vector<std::uint8_t> stuck;

  void resize(std::size_t rows) {
    for (auto* column : {&x_r_m, &v_r_m_per_s, &a_x_m_per_s2, &friction_n}) column->resize(rows);
    stuck.resize(rows);
  }

  // Appends `other`'s rows after this trace's (a run made in parts).
  void append(const SimulationTrace& other) {
    x_r_m.insert(x_r_m.end(), other.x_r_m.begin(), other.x_r_m.end());
    v_r_m_per_s.insert(v_r_m_per_s.end(), other.v_r_m_per_s.begin(), other.v_r_m_per_s.end());
    a_x_m_per_s2.insert(a_x_m_per_s2.end(), other.a_x_m_per_s2.begin(), other.a_x_m_per_s2.end());
    friction_n.insert(friction_n.end(), other.friction_n.begin(), other.friction_n.end());
    stuck.insert(stuck.end(), other.stuck.begin(), other.stuck.end());
  }

  void store(std::size_t row, const StepOutput<T>& out) {
    x_r_m[row] = out.x_r_m;
    v_r_m_per_s[row] = out.v_r_m_per_s;
    a_x_m_per_s2[row] = out.a_x_m_per_s2;
    friction_n[row] = out.friction_n;
    stuck[row] = out.stuck ? 1 : 0;
  }
};

struct SimulationSummary {
  std::uint64_t samples = 0;  // rows, the initial one included
  std::uint64_t steps = 0;    // samples - 1
  double dt_s = 0.0;
  double rms_u = 0.0;              // m/s^2
  double rms_x = 0.0;              // m/s^2
  double transmissibility = 0.0;   // T_ax = rms_x / rms_u
  double stick_probability = 0.0;  // p
  double den_hartog_k = 0.0;       // K from F_fk, m and rms_u (for any model)
  double ns_per_sample = 0.0;      // median wall time of the loop per step
  int repetitions = 0;
  std::uint64_t events = 0;                  // in-step stick/break-away/reversal events
  std::uint64_t rejected_inputs = 0;         // non-finite input samples replaced
  std::uint64_t event_budget_exhausted = 0;  // steps that hit the event budget
  std::uint64_t state_resets = 0;            // non-finite state restarts
  // The seat with end stops: contacts begun over the run.
  bool end_stops = false;
  std::uint64_t end_stop_contacts = 0;
  // ISO 2631-1 ride comfort of the run (Wk, vertical; floor = a_u, seat = a_x), computed from the
  // trace after the timed loop (add_ride_comfort()).
  bool comfort = false;
  double floor_weighted_rms = 0.0, seat_weighted_rms = 0.0;  // m/s^2
  double seat_ratio = 0.0;                                   // SEAT
  double seat_vdv = 0.0;                                     // m/s^1.75
  double seat_mtvv = 0.0;                                    // m/s^2, 1 s running RMS maximum
  double seat_crest_factor = 0.0;
  // The ECU node's observer (observer/observer.hpp) at the end of the stream: its last full
  // window (10 s) and its regime with hysteresis.
  bool observed = false;
  double window_s = 0.0, window_transmissibility = 0.0, window_stick_probability = 0.0;
  double window_den_hartog_k = 0.0;
  std::uint32_t window_stick_events = 0, window_slip_events = 0, regime_changes = 0;
  std::string observer_regime;
  std::uint64_t saturated_steps = 0;  // fixed point: steps in which a value saturated
};

// Whether a model is the seat with end stops, and the contacts it has begun (0 for any other
// model): the one test every runner of a scene's model makes.
template <typename Model>
inline constexpr bool kHasEndStops =
    std::is_same_v<Model, EndStopOscillator<typename Model::Scalar, typename Model::FrictionLaw>>;
template <typename Model>
std::uint64_t end_stop_contacts(const Model& model) noexcept {
  if constexpr (kHasEndStops<Model>) {
    return model.contacts();
  } else {
    (void)model;
    return 0;
  }
}

// The summary's run figures from a run's statistics and its model's counters (any scalar type,
// any model with rejected_inputs(), event_budget_exhausted(), state_resets()): the one place
// simulate, simulate --scalar fixed and the ECU node fill them.
template <typename Statistics, typename Model>
void summarise_run(SimulationSummary& summary, const Statistics& statistics, const Model& model,
                   std::uint64_t events) {
  if constexpr (kHasEndStops<Model>) {
    summary.end_stops = true;
    summary.end_stop_contacts = end_stop_contacts(model);
  }
  summary.samples = statistics.samples();
  summary.steps = statistics.steps();
  summary.rms_u = statistics.rms_u();
  summary.rms_x = statistics.rms_x();
  summary.transmissibility = statistics.transmissibility();
  summary.stick_probability = statistics.stick_probability();
  summary.events = events;
  summary.rejected_inputs = model.rejected_inputs();
  summary.event_budget_exhausted = model.event_budget_exhausted();
  summary.state_resets = model.state_resets();
}

// Copies a ride-comfort accumulator's figures into the summary (simulate's whole-trace pass and
// the ECU node's running observer report the same keys).
template <typename Comfort>
void summarise_comfort(SimulationSummary& summary, const Comfort& comfort) {
  summary.comfort = comfort.samples() > 0;
  summary.floor_weighted_rms = comfort.floor_weighted_rms();
  summary.seat_weighted_rms = comfort.seat_weighted_rms();
  summary.seat_ratio = comfort.seat_ratio();
  summary.seat_vdv = comfort.seat_vdv();
  summary.seat_mtvv = comfort.seat_mtvv();
  summary.seat_crest_factor = comfort.seat_crest_factor();
}

// Fills the summary's ride-comfort figures from a finished run's input and seat acceleration
// (RideComfort<double>, Wk at 1/dt_s); throws ConfigurationError if the weighting refuses dt_s.
template <typename T>
void add_ride_comfort(SimulationSummary& summary, const std::vector<double>& a_u,
                      const std::vector<T>& a_x, double dt_s);

// Configures the oscillator for setup.params (throws ConfigurationError if configure() refuses),
// then runs reset(x0, v0, a_u[0]) and step(a_u[n]) for n >= 1 `repetitions` times, each time
// filling `trace` (resized here, outside the timed loop) and the statistics. Needs >= 2 samples.
// With setup.reference, times solve_reference() instead (the same statistics; p from its exact
// stuck time); T = float is then refused with a UsageError.
template <typename T>
SimulationSummary simulate_signal(const SimulationSetup& setup, const std::vector<T>& a_u,
                                  SimulationTrace<T>& trace);

// --scalar fixed: as simulate_signal, with the oscillator in fixed point (Q23.40). The input is
// converted once, before the loop (a sample beyond the format saturates and is counted in
// saturated_steps like any saturation in the step); the trace and the statistics hold the outputs
// converted exactly to double. Models and integrators fixed point does not offer are refused by
// configure() (ConfigurationError), as are scenes whose values would not fit.
SimulationSummary simulate_signal_fixed(const SimulationSetup& setup,
                                        const std::vector<double>& a_u,
                                        SimulationTrace<double>& trace);

// --scalar fixed32: as simulate_signal_fixed, with ScaledOscillator<Fixed32, Law> (with end stops
// ScaledEndStopOscillator<Fixed32, Law>): the scene in the units configure() chooses from the
// declared ranges, the input converted to them once per sample and the outputs converted back to
// SI (double) for the trace and the statistics.
SimulationSummary simulate_signal_fixed32(const SimulationSetup& setup,
                                          const std::vector<double>& a_u,
                                          SimulationTrace<double>& trace);

}  // namespace stickslip::host
