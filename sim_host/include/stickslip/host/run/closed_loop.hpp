// `stickslip closed-loop` as functions: the seat in a loop with a controller over a recording
// (the per-sample loop itself is the core's ClosedLoop, control/closed_loop.hpp), its comfort
// against the passive seat, and a sweep of the controller's gain.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stickslip/control/closed_loop.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

// The controllers `--controller` names. skyhook/groundhook: the active hook laws; -semi: the
// controllable damper between b_min and b_max; friction-compensation: the feed-forward alone.
enum class ControllerChoice : std::uint8_t {
  passive,
  skyhook,
  groundhook,
  skyhook_semi,
  groundhook_semi,
  friction_compensation
};
const char* controller_name(ControllerChoice choice) noexcept;
bool parse_controller(const std::string& name, ControllerChoice& out) noexcept;
std::vector<std::string> controller_names();

struct ClosedLoopSetup {
  SimulationSetup plant;  // the seat and its scene; dt_s from the recording
  ControllerChoice controller = ControllerChoice::passive;
  double gain_ns_per_m = 1500.0;         // the hook's c
  double min_damping_ns_per_m = 0.0;     // semi-active b_min
  double max_damping_ns_per_m = 3000.0;  // semi-active b_max
  double friction_compensation = 0.0;    // fraction fed forward (friction-compensation: 0.8)
  double force_limit_n = 1000.0;         // actuator
  double actuator_lag_s = 0.0;           // actuator's first-order lag
  ObserverKind observer = ObserverKind::estimator;
  // Sensors: white Gaussian noise (RMS per sample) and resolution of a_x and x_r.
  double a_x_noise_m_per_s2 = 0.0, x_r_noise_m = 0.0;
  double a_x_resolution_m_per_s2 = 0.0, x_r_resolution_m = 0.0;
  // The bus between plant and controller (0: none): a_u as the controller receives it and the
  // force as the command frame carries it (set_can_resolution()).
  double a_u_resolution_m_per_s2 = 0.0, force_resolution_n = 0.0;
  std::uint64_t seed = 1;
  // In process only: the user's controller (LoopController::user) instead of `controller`.
  const UserController<double>* user = nullptr;
};

// The core's loop parameters for a setup at step dt_s (the observer's seat from the plant).
ClosedLoopParams closed_loop_params(const ClosedLoopSetup& setup, double dt_s);

// The resolutions of the CAN frames between `stickslip plant` and `stickslip controller`
// (SeatInput a_u, SeatSensors a_x and x_r, ActuatorCommand f_a): the in-process loop with these
// is the loop over the bus, bit for bit (closed-loop --can-resolution).
void set_can_resolution(ClosedLoopSetup& setup);

// One row per input sample, as simulate's trace, plus the force held over the step into the row
// (f_a[0] = 0) and what the controller read and commanded at that sample.
struct ClosedLoopTrace {
  SimulationTrace<double> plant;
  std::vector<double> f_a_n;               // force over the step ending at sample n
  std::vector<double> command_n;           // controller's command at sample n (before the actuator)
  std::vector<double> sensed_v_r_m_per_s;  // the v_r the controller read at sample n
};

// Comfort and effort of one run (passive or controlled).
struct ControlFigures {
  std::uint64_t samples = 0;
  double transmissibility = 0.0;   // T_ax = RMS(a_x)/RMS(a_u), as simulate's
  double stick_probability = 0.0;  // p
  double seat_weighted_rms = 0.0, floor_weighted_rms = 0.0;  // ISO 2631-1 Wk, m/s^2
  double seat_ratio = 0.0;  // SEAT = seat_weighted_rms / floor_weighted_rms
  double vdv = 0.0;         // m/s^1.75
  double travel_m = 0.0;    // peak |x_r|
  double force_rms_n = 0.0, force_peak_n = 0.0;
  // Mean power of the actuator into the seat's relative motion, sum f_a[n] (x_r[n] - x_r[n-1])
  // over the run's duration: exact for the force held over each step. Positive: the actuator
  // puts energy in; negative: it takes energy out (a damper).
  double mean_power_w = 0.0;
  // Contacts with the end stops begun over the run (a scene with end stops; 0 without).
  std::uint64_t end_stop_contacts = 0;
};

// Runs the loop over a_u (one continuous part, >= 2 samples) and fills `trace`; the plant is
// the scene's model (with end stops: EndStopOscillator). Throws ConfigurationError when the core
// refuses the parameters.
ControlFigures run_closed_loop(const ClosedLoopSetup& setup, const std::vector<double>& a_u,
                               ClosedLoopTrace& trace);

// The figures of a finished run (the passive one: f_a empty).
ControlFigures measure_control(const std::vector<double>& a_u, const SimulationTrace<double>& trace,
                               const std::vector<double>& f_a_n, double dt_s);

// The trace CSV t,a_u,x_r,v_r,a_x,f_f,stuck,f_a of a closed-loop run (closed-loop and plant).
void write_loop_trace(CsvWriter& writer, const std::vector<double>& t_s,
                      const std::vector<double>& a_u, const ClosedLoopTrace& trace);

// The figures as closed-loop's JSON prints them (controlled: with the force figures).
std::string control_figures_json(const ControlFigures& figures, bool controlled,
                                 bool end_stops = false);

// Gain sweep: `count` gains from `low` to `high` (both included, evenly spaced).
struct GainSweep {
  double low_ns_per_m = 0.0, high_ns_per_m = 0.0;
  int count = 0;  // 0: no sweep
};
// "LO:HI:N" -> GainSweep; throws UsageError naming --sweep-gain.
GainSweep parse_gain_sweep(const std::string& text);
std::vector<double> sweep_gains(const GainSweep& sweep);

struct ClosedLoopRequest {
  std::string input_path;
  std::string output_path;  // trace CSV; with a sweep: the sweep's CSV
  std::string stats_path;   // empty: none
  std::string plot_path;    // sweep: the Pareto plot (PNG); empty: none
  ClosedLoopSetup setup;
  GainSweep sweep;
  RecordingOptions recording;
  std::string scene_path;
  double scene_dt_s = 0.0;
};

struct ClosedLoopResult {
  std::string json;        // one line
  std::string sweep_rows;  // sweep: the table printed for a person (one row per gain)
  RecordingReport recording;
};

// Reads the recording, runs passive and controlled (or the sweep), writes the outputs atomically.
ClosedLoopResult closed_loop_file(const ClosedLoopRequest& request);

}  // namespace stickslip::host
