#include "report/bench_step_results.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "report/text.hpp"

namespace stickslip::tradeoff::report {

std::vector<BatchResult> batch_speedups(const std::string& json_text) {
  std::vector<BatchResult> out;
  if (json_text.empty()) return out;
  const nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
  if (document.is_discarded() || !document.contains("benchmarks")) return out;
  std::map<std::string, double> medians, singles_run;
  for (const auto& b : document["benchmarks"]) {
    if (!b.contains("items_per_second") || !b.contains("run_name")) continue;
    const std::string name = b["run_name"].get<std::string>();
    const double items = b["items_per_second"].get<double>();
    if (b.value("run_type", "") == "aggregate") {
      if (b.value("aggregate_name", "") == "median") medians[name] = items;
    } else {
      singles_run[name] = items;
    }
  }
  const std::map<std::string, double>& items = medians.empty() ? singles_run : medians;
  for (const auto& [name, value] : items) {
    if (name.rfind("batch/", 0) != 0) continue;
    const auto single = items.find("singles/" + name.substr(6));
    if (single == items.end() || !(single->second > 0.0)) continue;
    out.push_back({name, value / single->second, value, single->second});
  }
  return out;
}

namespace {

// The count at the start of a callgrind_annotate line ("1,234,567 (12.3%) ...").
double annotate_count(const std::string& line) {
  std::string digits;
  for (char c : line) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      digits += c;
    } else if (c != ',' && c != ' ') {
      break;
    }
  }
  return digits.empty() ? 0.0 : std::strtod(digits.c_str(), nullptr);
}

}  // namespace

BatchProfile read_batch_profile(const std::string& dir, const std::string& name) {
  BatchProfile p;
  p.name = name;
  std::string tag = name;
  std::replace(tag.begin(), tag.end(), '/', '_');
  const nlohmann::json document =
      nlohmann::json::parse(read_text(dir + "/" + tag + ".json"), nullptr, false);
  if (document.is_discarded() || !document.contains("benchmarks") || document["benchmarks"].empty())
    return p;
  const auto& b = document["benchmarks"][0];
  if (!b.contains("lane_steps") || !b.contains("iterations")) return p;
  p.lane_steps = b["lane_steps"].get<double>() * b["iterations"].get<double>();
  std::istringstream lines(read_text(dir + "/" + tag + ".txt"));
  std::string line;
  const std::string loop = name.rfind("batch/", 0) == 0 ? "run_batch<" : "run_stream<";
  while (std::getline(lines, line)) {
    if (line.find("PROGRAM TOTALS") != std::string::npos)
      p.total = annotate_count(line);
    else if (line.find(loop) != std::string::npos && p.common_path == 0.0)
      p.common_path = annotate_count(line);
  }
  return p;
}

}  // namespace stickslip::tradeoff::report
