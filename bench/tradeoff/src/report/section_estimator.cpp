// The state estimator's cost per sample (bench/estimator/, stickslip_bench_state_estimator) and
// its ratio to the plain step of the model it corrects, both from the same benchmark run.
#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "report/sections.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {
namespace {

// "run DATE, load average L" from the benchmark's own context (empty when missing).
std::string run_context(const std::string& json_text) {
  const nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
  if (document.is_discarded() || !document.contains("context")) return {};
  const nlohmann::json& context = document["context"];
  std::string text;
  if (context.contains("date") && context["date"].is_string())
    text = "run " + context["date"].get<std::string>();
  if (context.contains("load_avg") && context["load_avg"].is_array() &&
      !context["load_avg"].empty() && context["load_avg"][0].is_number()) {
    text += fmt::format("{}load average {:.1f}", text.empty() ? "" : ", ",
                        context["load_avg"][0].get<double>());
  }
  return text;
}

// ns per sample (CPU time: Google Benchmark's items_per_second) by benchmark name: the median
// aggregate when the run had repetitions, else the single run. Empty for empty or malformed text.
std::map<std::string, double> ns_per_sample(const std::string& json_text) {
  std::map<std::string, double> medians, singles;
  if (json_text.empty()) return medians;
  const nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
  if (document.is_discarded() || !document.contains("benchmarks")) return medians;
  for (const auto& b : document["benchmarks"]) {
    if (!b.contains("items_per_second") || !b.contains("run_name")) continue;
    const double items = b["items_per_second"].get<double>();
    if (!(items > 0.0)) continue;
    const std::string name = b["run_name"].get<std::string>();
    if (b.value("run_type", "") == "aggregate") {
      if (b.value("aggregate_name", "") == "median") medians[name] = 1e9 / items;
    } else {
      singles[name] = 1e9 / items;
    }
  }
  return medians.empty() ? singles : medians;
}

}  // namespace

void section_estimator(std::ostream& md, const std::string& bench_json) {
  md << "## The state estimator: cost per sample\n\n";
  const std::map<std::string, double> ns_of = ns_per_sample(bench_json);
  const auto find = [&ns_of](const std::string& name) {
    const auto it = ns_of.find(name);
    return it == ns_of.end() ? std::nan("") : it->second;
  };
  const double plain_double = find("plain_step<double>");
  const double plain_float = find("plain_step<float>");
  if (!(plain_double > 0.0) || !(plain_float > 0.0)) {
    md << "`stickslip_bench_state_estimator` was not built or did not run when this report ran, "
          "so the estimator's cost is not measured.\n\n";
    return;
  }
  const std::string context = run_context(bench_json);
  md << "`stickslip_bench_state_estimator` (Google Benchmark, bench/estimator/"
     << (context.empty() ? "" : "; " + context)
     << ") as this report ran it: the state estimator (`observer/state_estimator.hpp`) on its "
        "validation scenario "
        "(floor RMS 0.6 m/s^2, seed 1, 100 s at 1 kHz, stuck about 71 % of the time), and in the "
        "same run the plain step of the model it corrects (`Oscillator`, stick-slip, exact "
        "integrator, F_fk = 60 N, F_fs = 70 N) on the same floor signal. Median of the "
        "repetitions, CPU time per sample; the ratio is to the plain step in the same scalar:\n\n";
  const auto cell = [](double value, double plain) {
    if (!(value > 0.0)) return std::string("–");
    return fmt::format("{} ns ({})", ns(value), times(value / plain));
  };
  Table table{{"", "double", "float"}, {}};
  table.rows.push_back(
      {"plain step (`Oscillator::step`)", ns(plain_double) + " ns", ns(plain_float) + " ns"});
  table.rows.push_back({"estimator, a_x + travel",
                        cell(find("double_stream/ax_and_travel"), plain_double),
                        cell(find("float_stream/ax_and_travel"), plain_float)});
  table.rows.push_back({"estimator, a_x only", cell(find("double_stream/ax_only"), plain_double),
                        cell(find("float_stream/ax_only"), plain_float)});
  table.rows.push_back({"estimator, travel only",
                        cell(find("double_stream/travel_only"), plain_double),
                        cell(find("float_stream/travel_only"), plain_float)});
  table.write(md);
  md << "The estimator's extra cost is the 3x3 covariance propagation and up to two scalar Kalman "
        "updates per sample (docs/IDENTIFICATION.md, \"Cost and numerics\"), where the plain step "
        "of a stuck seat is a test and a copy.\n\n";
}

}  // namespace stickslip::tradeoff::report
