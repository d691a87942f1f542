// stickslip_bench_step's results as the report reads them: batch against singles throughput from
// Google Benchmark's JSON, and the callgrind counts of one run of each (the batch profile).
#pragma once

#include <string>
#include <vector>

namespace stickslip::tradeoff::report {

struct BatchResult {
  std::string name;
  double speedup = 0.0;
  double batch_items = 0.0, single_items = 0.0;
};

// batch/<scalar>/N<lanes>... against singles/<scalar>/N<lanes>... (the same name after the prefix)
// from Google Benchmark's JSON output: the median aggregate when the run had repetitions, else the
// single run. (Its CSV reporter refuses benchmarks with differing counters.) None for empty or
// malformed text.
std::vector<BatchResult> batch_speedups(const std::string& json_text);

struct BatchProfile {
  std::string name;          // e.g. batch/double/N8/own-inputs
  double lane_steps = 0.0;   // lane-steps of the profiled run (lane_steps counter x iterations)
  double total = 0.0;        // instructions inside run_batch / run_stream, callees included
  double common_path = 0.0;  // of which in the loop function itself (the inlined step + statistics)
  bool ok() const { return lane_steps > 0.0 && total > 0.0; }
};

// From <dir>/<tag>.json (one iteration's --benchmark_out) and <dir>/<tag>.txt
// (callgrind_annotate --inclusive=no), tag = the name with '/' as '_'. Not ok() when missing.
BatchProfile read_batch_profile(const std::string& dir, const std::string& name);

}  // namespace stickslip::tradeoff::report
