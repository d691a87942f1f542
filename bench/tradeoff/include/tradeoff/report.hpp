// docs/PERFORMANCE.md from the harness's CSV and the facts the report script gathered, plus the
// gnuplot script and data for the Pareto plots. Written from scratch every time: nothing in it is
// edited by hand.
#pragma once

#include <string>

namespace stickslip::tradeoff {

struct ReportRequest {
  std::string results_csv;   // the run's CSV
  std::string results_link;  // how the .md links to it (relative to the .md)
  std::string
      machine_file;  // "key: value" lines: cpu, cores, os, compiler, flags, date, commit ...
  std::string profile_dump;     // callgrind dump of the headline configuration (optional)
  std::string bench_step_text;  // stickslip_bench_step console output (optional)
  std::string bench_step_json;  // the same run's --benchmark_out JSON (optional)
  // Directory with, per profiled benchmark <tag> (its name with '/' as '_'): <tag>.json (one
  // iteration's --benchmark_out) and <tag>.txt (callgrind_annotate --inclusive=no of the run with
  // collection on inside run_batch/run_stream only). Optional.
  std::string batch_profile_dir;
  std::string bench_step_avx2_json;  // batch vs singles built with -march=x86-64-v3 (optional)
  std::string bench_estimator_json;  // stickslip_bench_state_estimator's JSON (optional)
  std::string output_md;
  std::string plot_dir;    // gnuplot data and pareto.gp are written here
  std::string image_link;  // directory of the PNGs, relative to the .md
  std::string command;     // the one command that reproduces the report
  double elapsed_s = 0.0;  // wall time of the command up to the report step (0: unknown)
};

// Throws host::HostError on unreadable input or an unwritable output.
void write_report(const ReportRequest& request);

// The report's state estimator section alone, from stickslip_bench_state_estimator's JSON, to
// `out` (what write_report() puts in docs/PERFORMANCE.md; for running that benchmark alone).
void write_estimator_section(std::ostream& out, const std::string& bench_estimator_json);

}  // namespace stickslip::tradeoff
