// The two soak paths. Each prints its checkpoints and a summary and returns the exit status:
// 0 all checks passed, 1 a check failed (or the scene was refused), 2 the CSV cannot be written.
#pragma once

#include "soak/options.hpp"

namespace stickslip::soak {

// The oscillator and RunningStatistics only, against the whole-stream recomputation.
template <typename T>
int soak_oscillator(const Options& o);

// Through the Observer as the ECU node drives it (sim_host/src/bus/ecu_node.cpp), with every
// statistic it publishes against the long-double oracle.
template <typename T>
int soak_observer(const Options& o);

}  // namespace stickslip::soak
