// The closed loop split over a CAN bus (docs/CONTROL.md, "The controller over CAN"):
//   plant       the seat under the cab-floor recording; each sample it sends SeatSensors (a_x,
//               x_r) and SeatInput (a_u) with the sample counter, and holds over the next step
//               the force of the ActuatorCommand answering that sample.
//   controller  observer + controller + actuator (ControlUnit, the code ClosedLoop runs in
//               process); answers each sample with an ActuatorCommand.
// The command answering sample n acts over step n -> n+1: the loop delay of closed-loop, so that
// with --pace max the trace equals `closed-loop --can-resolution` bit for bit.
// Fault policy at the plant: an answer missing (lost, late, corrupt) holds the last force for
// hold_frames samples, then the plant fails safe (f_a = 0) until answers come again; a bus that
// goes down makes the plant passive for the rest of the run. Every such sample is counted.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stickslip/host/run/closed_loop.hpp"
#include "stickslip/port/transport.hpp"

namespace stickslip::host {

enum class Pace : unsigned char { max, realtime };

struct PlantNodeRequest {
  std::string input_path;
  std::string output_path;  // trace CSV as closed-loop's
  std::string stats_path;   // empty: none
  ClosedLoopSetup setup;    // the seat, its scene and the sensor noise (resolutions: the bus's)
  RecordingOptions recording;
  std::string scene_path;
  double scene_dt_s = 0.0;
  std::string bus = "loopback";
  Pace pace = Pace::max;
  int hold_frames = 3;             // missing answers bridged with the last force
  double command_timeout_s = 0.5;  // pace max: the wait for each answer
  double connect_timeout_s = 5.0;  // the wait for the answer to sample 0 (re-sent every 100 ms)
  // Tests: an open endpoint to use instead of opening `bus`.
  port::Transport* transport = nullptr;
};

struct PlantCounters {
  std::uint64_t commands_applied = 0;       // answers in time, force applied
  std::uint64_t commands_passive = 0;       // of those, answers asking for no force
  std::uint64_t commands_missing = 0;       // samples whose answer did not come in time
  std::uint64_t commands_late = 0;          // answers that came after their sample's step (ignored)
  std::uint64_t commands_corrupt = 0;       // CRC errors, wrong length (ignored)
  std::uint64_t held_frames = 0;            // steps under the held last force
  std::uint64_t failsafe_frames = 0;        // steps passive because answers were missing
  std::uint64_t bus_down_frames = 0;        // steps passive because the bus was down
  std::uint64_t first_failsafe_sample = 0;  // 0: none
  std::uint64_t last_failsafe_sample = 0;   // where the last run of fail-safe steps began
  std::uint64_t bus_down_sample = 0;        // 0: the bus stayed up
};

// Wake-up lateness of a real-time paced run (pace realtime).
struct PacingReport {
  std::uint64_t ticks = 0;
  std::uint64_t deadline_misses = 0;  // ticks woken a whole period or more late
  double lateness_median_s = 0.0, lateness_p999_s = 0.0, lateness_worst_s = 0.0;
};

struct PlantNodeResult {
  double dt_s = 0.0;
  ControlFigures figures;
  PlantCounters counters;
  PacingReport pacing;
  std::string state;  // "ok", "failsafe" (answers missing at the end), "bus_down"
  std::string json;
  std::string bus_message;  // the line saying the bus went down (empty: it did not)
  RecordingReport recording;
};

PlantNodeResult run_plant_node(const PlantNodeRequest& request);

struct ControllerNodeRequest {
  ClosedLoopSetup setup;  // controller, actuator, the seat the observer assumes
  std::string bus = "loopback";
  double idle_exit_s = 2.0;     // exit after this long without a sample (once one came)
  double first_sample_s = 0.0;  // wait this long for the first sample (0: without limit)
  // Fault injection (tests, docs): drop every k-th answer (0: none), stop answering from this
  // sample time on (< 0: never).
  std::uint64_t drop_every = 0;
  double stop_after_s = -1.0;
  port::Transport* transport = nullptr;  // tests: an open endpoint
  std::function<bool()> stop_requested;  // e.g. SIGINT/SIGTERM
  std::function<void()> listening;       // called once the bus is open and filtered
};

struct ControllerNodeResult {
  std::uint64_t samples = 0;         // samples received whole (sensors + input)
  std::uint64_t answered = 0;        // ActuatorCommand frames sent
  std::uint64_t dropped = 0;         // answers dropped by drop_every
  std::uint64_t silenced = 0;        // samples not answered after stop_after_s
  std::uint64_t corrupt_frames = 0;  // CRC or length errors
  std::uint64_t sample_gaps = 0;     // samples skipped in the counter sequence
  std::uint64_t restarts = 0;        // sample 0 received again (the plant's greeting re-sent)
  std::uint64_t send_failures = 0;
  std::string bus_error;  // the line saying the bus failed (empty: it did not)
  std::string json;
};

ControllerNodeResult run_controller_node(const ControllerNodeRequest& request);

}  // namespace stickslip::host
