// The statistics of a simulate run as one JSON object on one line. The first keys are the
// contract other tools read: samples, dt, rms_u, rms_x, T_ax, p_stick, K, ns_per_sample; the
// rest describe the run. Non-finite numbers (K with no excitation) are written as null.
#pragma once

#include <string>

#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

struct StatsContext {
  const SimulationSetup* setup;
  ScalarType scalar;
  std::string input_path;
  std::string output_path;
};

std::string format_stats_json(const SimulationSummary& summary, const StatsContext& context);

}  // namespace stickslip::host
