// The host commands as functions (the command line in cli.cpp only parses options into these
// requests): generate is write_generated_csv() in signal_generator.hpp; simulate and demo here.
#pragma once

#include <iosfwd>
#include <string>

#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

struct SimulateRequest {
  std::string input_path;
  std::string output_path;
  std::string stats_path;  // empty: no stats file
  SimulationSetup setup;   // dt_s is taken from the input file
  ScalarType scalar = ScalarType::float64;
  std::string scene_path;   // --scene: checked against the input's dt when it names a sample rate
  double scene_dt_s = 0.0;  // 0: the scene names no sample rate
};

struct SimulateResult {
  SimulationSummary summary;
  std::string stats_json;  // one line, no newline
};

// Reads the input, simulates, writes OUT.csv (and the stats file) atomically. Throws HostError
// with a one-line message (file:line: problem) and leaves no output behind on any failure.
SimulateResult simulate_file(const SimulateRequest& request);

// The header simulate writes.
inline constexpr const char* kSimulateHeader = "t,a_u,x_r,v_r,a_x,f_f,stuck";

struct DemoRequest {
  double duration_s = 120.0;
  double dt_s = 1e-3;
  double friction_n = 45.0;  // F_fk = F_fs
  std::string out_dir;       // empty: a fresh directory under the system temp directory
  std::string bus;           // replay bus; empty: port::default_bus_name()
};

// Lorry recording (rms 0.35 m/s^2, seed 1) -> signum and stick-slip on the reference system ->
// a table and one sentence on which model the scene needs; then the recording replayed as CAN
// frames over the bus to the ECU node (stick-slip), with its fault counters and the check that
// simulate on the quantised samples gives the same output bit for bit; printed to `out`.
void run_demo(const DemoRequest& request, std::ostream& out);

}  // namespace stickslip::host
