// write_report: reads the inputs once, writes the plot data, then the sections in order into a
// temporary file that replaces the output only when complete.
#include "tradeoff/report.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "report/pareto_plot.hpp"
#include "report/sections.hpp"
#include "report/text.hpp"
#include "stickslip/host/error.hpp"
#include "tradeoff/callgrind_dumps.hpp"
#include "tradeoff/csv_table.hpp"

namespace stickslip::tradeoff {
namespace {

using Figures = std::vector<std::pair<std::string, std::string>>;  // scene, PNG

// The plotted scenes this run has, each with its PNG name; their gnuplot data and script.
Figures write_plots(const report::Results& results, const std::string& plot_dir) {
  std::error_code error;
  std::filesystem::create_directories(plot_dir, error);
  if (error) throw host::HostError(plot_dir + ": " + error.message());
  Figures figures;
  for (const char* scene : {"lorry-K0.8-b504", "lorry-K0.2-b504", "lorry-K1.5-b504",
                            "lorry-K0.8-b0", "wideband-K0.8-b504", "harmonic-K0.8-b504"}) {
    if (results.has_scene(scene)) figures.emplace_back(scene, fmt::format("pareto-{}.png", scene));
  }
  report::write_gnuplot(results, plot_dir, figures);
  return figures;
}

void section_pareto(std::ostream& md, const Figures& figures, const std::string& image_link) {
  md << "## Pareto plots\n\n";
  for (const auto& [scene, png] : figures) {
    md << fmt::format("![{}: error vs cost]({}/{})\n\n", scene, image_link, png);
  }
  md << "Along a curve dt runs from 0.1 ms to 10 ms; the cost per *sample* hardly depends on dt "
        "(the cost "
        "per simulated second does, by 1/dt), the error does.\n\n";
}

void section_full_results(std::ostream& md, const ReportRequest& request,
                          const report::Results& results) {
  md << "## Full results\n\n";
  std::string columns;
  for (const std::string& name : column_names())
    columns += (columns.empty() ? "`" : ", `") + name + "`";
  md << fmt::format(
      "Every row of the run: [{}]({}) ({} rows). Columns: {}. Empty cells: not applicable (e.g. "
      "p for models without a stuck state, errors of refused runs).\n",
      std::filesystem::path(request.results_link).filename().string(), request.results_link,
      results.rows.size(), columns);
}

}  // namespace

void write_report(const ReportRequest& request) {
  using namespace report;
  Results results(read_rows(request.results_csv));
  if (results.rows.empty()) throw host::HostError(request.results_csv + ": no results");
  const Facts facts = read_facts(request.machine_file);
  const CallgrindDump profile =
      read_callgrind_dump(request.profile_dump, CallgrindDetail::self_costs);
  const std::string bench_text = read_text(request.bench_step_text);
  const std::vector<BatchResult> batches = batch_speedups(read_text(request.bench_step_json));
  const Figures figures = write_plots(results, request.plot_dir);

  const std::string temporary = request.output_md + ".partial";
  std::ofstream md(temporary);
  if (!md) throw host::HostError(temporary + ": cannot open for writing");
  section_reproduce(md, request, facts);
  section_machine(md, facts);
  section_method(md, results, facts);
  section_targets(md, results, batches, !bench_text.empty(), profile);
  section_pareto(md, figures, request.image_link);
  section_recommendation(md, results);
  section_peers(md, results, profile);
  section_headline_table(md, results);
  section_model_vs_solver(md, results);
  section_scene_summary(md, results);
  section_refusals(md, results);
  section_profile(md, results, profile);
  section_bench_step(md, bench_text);
  section_batch_profile(md, request, batches);
  section_estimator(md, read_text(request.bench_estimator_json));
  section_full_results(md, request, results);
  md.close();
  if (!md) throw host::HostError(temporary + ": write failed");
  std::error_code error;
  std::filesystem::rename(temporary, request.output_md, error);
  if (error) throw host::HostError(request.output_md + ": " + error.message());
}

void write_estimator_section(std::ostream& out, const std::string& bench_estimator_json) {
  const std::string text = report::read_text(bench_estimator_json);
  if (text.empty()) throw host::HostError(bench_estimator_json + ": missing or empty");
  report::section_estimator(out, text);
}

}  // namespace stickslip::tradeoff
