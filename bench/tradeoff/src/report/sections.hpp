// The sections of docs/PERFORMANCE.md, in the order write_report() puts them. Each writes its own
// heading and reads only what it is given.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "report/bench_step_results.hpp"
#include "report/results_view.hpp"
#include "tradeoff/callgrind_dumps.hpp"
#include "tradeoff/report.hpp"

namespace stickslip::tradeoff::report {

using Facts = std::map<std::string, std::string>;

// Title, provenance, how to reproduce (section_method.cpp).
void section_reproduce(std::ostream& md, const ReportRequest& request, const Facts& facts);
void section_machine(std::ostream& md, const Facts& facts);
// What this run covered, from the rows themselves (the command line may have narrowed it).
void section_method(std::ostream& md, const Results& results, const Facts& facts);

// The targets and their verdicts (section_targets.cpp).
void section_targets(std::ostream& md, const Results& results,
                     const std::vector<BatchResult>& batches, bool bench_step_ran,
                     const CallgrindDump& profile);

void section_recommendation(std::ostream& md, const Results& results);
void section_peers(std::ostream& md, const Results& results, const CallgrindDump& profile);

// Tables of the rows (section_tables.cpp).
void section_headline_table(std::ostream& md, const Results& results);
void section_model_vs_solver(std::ostream& md, const Results& results);
void section_scene_summary(std::ostream& md, const Results& results);
void section_refusals(std::ostream& md, const Results& results);

// Where the time of the headline configuration goes, from its callgrind dump.
void section_profile(std::ostream& md, const Results& results, const CallgrindDump& profile);

// stickslip_bench_step's output and why batch mode falls short (section_batch.cpp).
void section_bench_step(std::ostream& md, const std::string& bench_text);
void section_batch_profile(std::ostream& md, const ReportRequest& request,
                           const std::vector<BatchResult>& batches);

// The state estimator's ns/sample and its ratio to the plain step, from
// stickslip_bench_state_estimator's --benchmark_out JSON (section_estimator.cpp).
void section_estimator(std::ostream& md, const std::string& bench_json);

}  // namespace stickslip::tradeoff::report
