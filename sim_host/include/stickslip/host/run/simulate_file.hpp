// `stickslip simulate` as a function: a recording in, the trace CSV and the statistics out.
#pragma once

#include <functional>
#include <string>

#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

// Called as each stage of simulate_file() starts ("reading IN.csv", "simulating N samples",
// "writing OUT.csv"), from the calling thread; empty: nobody is told.
using StageReport = std::function<void(const std::string& stage)>;

struct SimulateRequest {
  std::string input_path;
  std::string output_path;
  std::string stats_path;  // empty: no stats file
  SimulationSetup setup;   // dt_s is taken from the recording (or --dt)
  ScalarType scalar = ScalarType::float64;
  std::string scene_path;   // --scene: checked against the input's dt when it names a sample rate
  double scene_dt_s = 0.0;  // 0: the scene names no sample rate
  StageReport on_stage;
  RecordingOptions recording;  // which signal, unit, gaps, and the model's step
};

struct SimulateResult {
  SimulationSummary summary;
  std::string stats_json;  // one line, no newline
  RecordingReport recording;
};

// Reads the input, simulates, writes OUT.csv (and the stats file) atomically. Throws HostError
// with a one-line message (file:line: problem) and leaves no output behind on any failure.
SimulateResult simulate_file(const SimulateRequest& request);

}  // namespace stickslip::host
