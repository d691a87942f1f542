// The two passes of the harness over a plan: `run` (references, traces, timing, peers -> CSV) and
// `count-instructions` (the streaming loop of every combination once under callgrind).
#pragma once

#include <iosfwd>
#include <string>

#include "tradeoff/combinations.hpp"

namespace stickslip::tradeoff {

struct RunRequest {
  Plan plan;
  std::string output_csv;        // written atomically (a temporary file renamed at the end)
  std::string instructions_dir;  // callgrind dumps of count-instructions; empty: no Ir column
};

// Throws host::HostError / host::UsageError with a one-line message.
void run_harness(const RunRequest& request, std::ostream& progress);

// Must run under valgrind --tool=callgrind --instr-atstart=no (refused otherwise).
void count_instructions(const Plan& plan, std::ostream& progress);

}  // namespace stickslip::tradeoff
