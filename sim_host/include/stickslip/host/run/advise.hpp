// `stickslip advise`: which model and integrator a recording needs. Runs the recording through
// the stick-slip model with the exact integrator (the reference: exact to rounding for the
// Coulomb model at any dt, docs/DESIGN.md) and through every cheaper candidate at the
// recording's own dt, times each on the spot (median ns/sample of repeated runs), and names the
// cheapest whose relative T_ax error stays within the tolerance. Costs within 10 % count as a tie
// (timing noise); the tie goes to the more accurate candidate.
#pragma once

#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/run/recording_source.hpp"

namespace stickslip::host {

struct AdviseRequest {
  std::string input_path;
  RecordingOptions recording;
  OscillatorParams params;  // model, integrator and dt are set per candidate
  double tolerance = 0.01;
  int repetitions = 3;  // timed runs per candidate
};

struct AdviseCandidate {
  FrictionModel model = FrictionModel::stick_slip;
  Integrator integrator = Integrator::exact;
  bool configured = false;  // false: configure() refused (e.g. unstable at this dt)
  std::string refusal;
  double transmissibility = 0.0;
  double stick_probability = 0.0;
  double relative_error = 0.0;  // |T_ax / T_ax,ref - 1|
  double ns_per_sample = 0.0;
  bool within_tolerance = false;
  // --gaps split: each part's T_ax and p (each part run alone from rest); the figures above are
  // over all parts (RMS weighted by samples, p by steps, as simulate reports them).
  std::vector<double> part_transmissibility, part_stick_probability;
};

struct AdviseReport {
  std::string input_path;
  std::string recording_note;  // what reading did to the samples, if anything
  double dt_s = 0.0;
  double a0u = 0.0;
  double k = 0.0;
  double tolerance = 0.0;
  AdviseCandidate reference;  // stick-slip, exact
  AdviseCandidate cheap;      // signum, euler (Simulink ode1): the model users usually run
  std::vector<AdviseCandidate> candidates;  // by cost, cheapest first
  int chosen = -1;                          // index into candidates
  // --gaps split: each part's first time and sample count (one entry when not split)
  std::vector<double> part_t_start_s;
  std::vector<std::size_t> part_samples;
};

AdviseReport advise(const AdviseRequest& request);

// The report as text: the figures, the table and one sentence naming the choice.
std::string format_advice(const AdviseReport& report);

}  // namespace stickslip::host
