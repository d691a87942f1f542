#include "tradeoff/report.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "stickslip/host/error.hpp"
#include "tradeoff/csv_table.hpp"

namespace stickslip::tradeoff {
namespace {

// ---- The targets -----------------------------------------------------------------------
constexpr double kTargetNsPerSample = 10.0;  // stick-slip, exact, double, streaming
constexpr double kTargetTaxRelErr = 1e-3;    // at dt = 1 ms on the lorry-like scene
constexpr double kTargetPAbsErr = 0.005;
constexpr double kTargetPeerRatio = 50.0;  // vs the fastest peer reaching the same T_ax error
constexpr double kTargetBatchSpeedup = 4.0;
constexpr double kHeadlineDtMs = 1.0;
const char* const kHeadlineScene = "lorry-K0.8-b504";

constexpr double kBands[] = {1e-1, 1e-2, 1e-3, 1e-4};  // relative T_ax error bands of the summaries
constexpr double kPlotFloor = 1e-15;  // errors below are drawn here on the log axes
// Runs whose median costs differ by less than this are ties (the timing noise of this machine);
// the recommendation then takes the more accurate one.
constexpr double kCostTie = 1.10;

// ---- Small helpers -----------------------------------------------------------------------------
bool same_dt(double a, double b) {
  return std::fabs(a - b) <= 1e-9 * std::max(a, b);
}

std::string ns(double value) {
  return value >= 100.0 ? fmt::format("{:.0f}", value) : fmt::format("{:.1f}", value);
}
std::string sci(double value) {
  return value == 0.0 ? "0" : fmt::format("{:.1e}", value);
}
std::string opt_sci(const std::optional<double>& value) {
  return value ? sci(*value) : "–";
}
std::string percent(double band) {
  return fmt::format("{:g} %", band * 100.0);
}
std::string dt_label(double dt_ms) {
  return fmt::format("{:g} ms", dt_ms);
}
std::string times(double ratio) {
  return fmt::format("{:.1f}x", ratio);
}

double median_of(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

std::string read_text(const std::string& path) {
  if (path.empty()) return {};
  std::ifstream in(path);
  if (!in) return {};
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::map<std::string, std::string> read_facts(const std::string& path) {
  std::map<std::string, std::string> facts;
  std::ifstream in(path);
  if (!in) throw host::HostError(path + ": cannot open the machine facts");
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    facts[line.substr(0, colon)] = value;
  }
  return facts;
}

std::string fact(const std::map<std::string, std::string>& facts, const std::string& key) {
  const auto found = facts.find(key);
  return found == facts.end() || found->second.empty() ? "unknown" : found->second;
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  void write(std::ostream& out) const {
    out << "|";
    for (const auto& h : header) out << " " << h << " |";
    out << "\n|";
    for (std::size_t i = 0; i < header.size(); ++i) out << "---|";
    out << "\n";
    for (const auto& row : rows) {
      out << "|";
      for (const std::string& c : row) {
        std::string escaped;  // a '|' inside a cell (code spans too) must be escaped in GFM tables
        for (const char ch : c) escaped += ch == '|' ? std::string("\\|") : std::string(1, ch);
        out << " " << escaped << " |";
      }
      out << "\n";
    }
    out << "\n";
  }
};

// ---- Views of the results ----------------------------------------------------------------------
struct Results {
  std::vector<Row> rows;
  std::vector<std::string> scenes;  // in CSV order
  std::vector<double> dts;          // sorted

  explicit Results(std::vector<Row> all) : rows(std::move(all)) {
    std::set<double> dt_set;
    for (const Row& r : rows) {
      if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end())
        scenes.push_back(r.scene);
      dt_set.insert(r.dt_ms);
    }
    dts.assign(dt_set.begin(), dt_set.end());
  }

  bool has_scene(const std::string& scene) const {
    return std::find(scenes.begin(), scenes.end(), scene) != scenes.end();
  }

  const Row* find(const std::string& scene, const std::string& model, const std::string& integrator,
                  const std::string& scalar, double dt_ms) const {
    for (const Row& r : rows) {
      if (r.implementation == "stickslip" && r.scene == scene && r.model == model &&
          r.integrator == integrator && r.scalar == scalar && same_dt(r.dt_ms, dt_ms)) {
        return &r;
      }
    }
    return nullptr;
  }

  const Row* first_of_scene(const std::string& scene) const {
    for (const Row& r : rows) {
      if (r.scene == scene) return &r;
    }
    return nullptr;
  }

  // Our fastest ok run on (scene, dt) with a T_ax error of at most `limit`.
  const Row* fastest_ours(const std::string& scene, double dt_ms, double limit) const {
    const Row* best = nullptr;
    for (const Row& r : rows) {
      if (r.implementation != "stickslip" || !r.ok() || r.scene != scene ||
          !same_dt(r.dt_ms, dt_ms) || !r.t_ax_rel_err || !r.ns_median || *r.t_ax_rel_err > limit) {
        continue;
      }
      if (!best || *r.ns_median < *best->ns_median) best = &r;
    }
    return best;
  }
};

// ---- Pareto plots (gnuplot) --------------------------------------------------------------------
struct Curve {
  std::string file, title, style;
};

// One curve per model/integrator (double) and per peer configuration through the dt values.
std::vector<Curve> write_scene_curves(const Results& results, const std::string& scene,
                                      const std::string& plot_dir) {
  std::map<std::string, std::vector<const Row*>> groups;
  std::vector<std::string> order;
  for (const Row& r : results.rows) {
    if (r.scene != scene || !r.ok() || !r.ns_median || !r.t_ax_rel_err) continue;
    if (r.implementation == "stickslip" && r.scalar != "double") continue;
    const std::string title =
        r.implementation == "odeint" ? r.configuration() : r.model + "/" + r.integrator;
    if (!groups.count(title)) order.push_back(title);
    groups[title].push_back(&r);
  }
  const std::map<std::string, std::string> colour = {
      {"linear", "#555555"},      {"signum", "#1f77b4"},     {"smooth-tanh", "#2ca02c"},
      {"smooth-atan", "#98df8a"}, {"smooth-erf", "#17becf"}, {"smooth-rational", "#bcbd22"},
      {"stick-slip", "#d62728"},  {"stribeck", "#9467bd"}};
  const std::map<std::string, int> point = {
      {"euler", 6}, {"symplectic", 8}, {"rk4", 4}, {"exact", 12}};
  std::vector<Curve> curves;
  for (const std::string& title : order) {
    std::vector<const Row*> points = groups[title];
    std::sort(points.begin(), points.end(),
              [](const Row* a, const Row* b) { return a->dt_ms < b->dt_ms; });
    const Row& first = *points.front();
    std::string file_name = scene + "--" + title + ".dat";
    for (char& c : file_name) {
      if (c == '/' || c == ' ') c = '_';
    }
    std::ofstream out(std::filesystem::path(plot_dir) / file_name);
    out << "# ns_per_sample t_ax_rel_err a_x_rms_err_rel dt_ms\n";
    for (const Row* r : points) {
      out << fmt::format("{:.6g} {:.6g} {:.6g} {:g}\n", *r->ns_median,
                         std::max(*r->t_ax_rel_err, kPlotFloor),
                         std::max(r->a_x_rms_err_rel.value_or(kPlotFloor), kPlotFloor), r->dt_ms);
    }
    Curve curve{file_name, title, {}};
    if (first.implementation == "odeint") {
      // Grey for the smoothed-signum peers, black for the event peer; the point type tells the
      // tolerance (1e-3, 1e-6, 1e-9, ...).
      const bool events = first.integrator == "odeint-dopri5-events";
      const int tolerance_index =
          first.tolerance ? static_cast<int>(std::lround(-std::log10(*first.tolerance) / 3.0)) : 0;
      curve.style = fmt::format("lc rgb '{}' dt {} pt {} lw 1.5", events ? "#000000" : "#8c8c8c",
                                first.integrator == "odeint-rk4" ? 3 : 2, 1 + tolerance_index);
    } else {
      const auto c = colour.find(first.model);
      const auto p = point.find(first.integrator);
      curve.style =
          fmt::format("lc rgb '{}' dt 1 pt {} lw 2", c == colour.end() ? "#000000" : c->second,
                      p == point.end() ? 1 : p->second);
    }
    curves.push_back(curve);
  }
  return curves;
}

void write_gnuplot(const Results& results, const std::string& plot_dir,
                   const std::vector<std::pair<std::string, std::string>>& figures) {
  std::ofstream gp(std::filesystem::path(plot_dir) / "pareto.gp");
  const std::string dts = fmt::format("{:g} ... {:g} ms", results.dts.front(), results.dts.back());
  gp << "# Generated by stickslip_tradeoff report. From this directory:\n"
        "#   gnuplot -e \"outdir='DIR'\" pareto.gp\n"
        "if (!exists('outdir')) outdir = '.'\n"
        "set terminal pngcairo size 1800,760 font 'Sans,11' noenhanced\n"
        "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
        "set format y '1e%T'\nset key outside right top vertical font ',9' spacing 1.05\n"
        "set xlabel 'median ns per sample (streaming loop: step + statistics)'\n";
  for (const auto& [scene, png] : figures) {
    const std::vector<Curve> curves = write_scene_curves(results, scene, plot_dir);
    if (curves.empty()) continue;
    gp << fmt::format("set output outdir.'/{}'\n", png);
    gp << fmt::format(
        "set multiplot layout 1,2 title '{}: error vs cost. One curve per model/integrator "
        "(double) "
        "through dt = {}; Boost.Odeint peers dashed (grey: smoothed signum, black: stick-slip with "
        "events). Errors below {:g} are drawn at {:g}.' font ',12'\n",
        scene, dts, kPlotFloor, kPlotFloor);
    const char* panels[2][2] = {{"2", "relative error of T_ax = RMS(a_x)/RMS(a_u), vs physics"},
                                {"3", "RMS error of the a_x history / RMS(a_x,ref), vs physics"}};
    for (int panel = 0; panel < 2; ++panel) {
      gp << "set ylabel '" << panels[panel][1] << "'\n"
         << (panel == 0 ? "unset key\n" : "set key\n");
      gp << "plot \\\n";
      for (std::size_t i = 0; i < curves.size(); ++i) {
        gp << fmt::format("  '{}' using 1:{} with linespoints {} title '{}'{}\n", curves[i].file,
                          panels[panel][0], curves[i].style, curves[i].title,
                          i + 1 < curves.size() ? ", \\" : "");
      }
    }
    gp << "unset multiplot\n";
  }
}

// ---- Callgrind profile -------------------------------------------------------------------------
// Self cost per source line and per function from a callgrind dump ("positions: line", the
// default). Call cost lines (the line after "calls=") are inclusive and skipped; relative positions
// (+n, -n, *) follow the last cost line, which a call's destination does not change.
struct Profile {
  double total = 0.0, steps = 0.0;
  std::map<std::pair<std::string, long>, double> lines;  // (file, line) -> Ir
  std::map<std::string, double> functions;               // function -> self Ir
};

Profile parse_callgrind_dump(const std::string& path) {
  Profile profile;
  std::ifstream in(path);
  if (path.empty() || !in) return profile;
  std::map<std::string, std::string> files, functions;
  const auto name = [](std::map<std::string, std::string>& names, const std::string& value) {
    if (value.empty() || value[0] != '(') return value;
    const std::size_t close = value.find(')');
    const std::string id = value.substr(0, close + 1);
    if (close + 2 < value.size()) names[id] = value.substr(close + 2);
    return names[id];
  };
  std::string line, function, function_file, file;
  long last = 0;
  bool call_cost_next = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line.rfind("desc: Trigger: Client Request: ", 0) == 0) {
      const std::size_t hash = line.rfind('#');
      if (hash != std::string::npos) profile.steps = std::strtod(line.c_str() + hash + 1, nullptr);
      continue;
    }
    const std::size_t eq = line.find('=');
    const std::string key = eq == std::string::npos ? std::string() : line.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : line.substr(eq + 1);
    if (key == "fl") {
      function_file = file = name(files, value);
    } else if (key == "fi" || key == "fe") {
      file = name(files, value);
    } else if (key == "cfi" || key == "cfl") {
      name(files, value);
    } else if (key == "fn") {
      function = name(functions, value);
      file = function_file;
    } else if (key == "cfn") {
      name(functions, value);
    } else if (key == "calls") {
      call_cost_next = true;
    } else if (key.empty() && (std::isdigit(static_cast<unsigned char>(line[0])) ||
                               line[0] == '+' || line[0] == '-' || line[0] == '*')) {
      std::istringstream cost(line);
      std::string position;
      double ir = 0.0;
      cost >> position >> ir;
      if (position[0] == '+' || position[0] == '-') {
        last += std::strtol(position.c_str(), nullptr, 10);
      } else if (position != "*") {
        last = std::strtol(position.c_str(), nullptr, 10);
      }
      if (call_cost_next) {
        call_cost_next = false;
        continue;
      }
      profile.lines[{file, last}] += ir;
      profile.functions[function] += ir;
      profile.total += ir;
    }
  }
  return profile;
}

// "lib/include/stickslip/models/oscillator.hpp" from the absolute path in the dump.
std::string repository_path(const std::string& path) {
  for (const char* root : {"lib/", "bench/", "sim_host/", "tests/"}) {
    const std::size_t at = path.rfind(std::string("/") + root);
    if (at != std::string::npos) return path.substr(at + 1);
  }
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : "<" + path.substr(slash + 1) + ">";
}

std::string source_line(const std::string& path, long number) {
  std::ifstream in(path);
  std::string line;
  for (long n = 1; n <= number && std::getline(in, line); ++n) {
  }
  line.erase(0, line.find_first_not_of(' '));
  if (line.size() > 100) line = line.substr(0, 97) + "...";
  return line;
}

// The qualified name without return type, template arguments, parameters and clone suffixes.
std::string short_function(const std::string& name) {
  std::string out;
  int depth = 0;
  for (const char c : name.substr(0, name.find(" [clone"))) {
    if (c == '<' || c == '(') ++depth;
    if (depth == 0) out += c;
    if ((c == '>' || c == ')') && depth > 0) --depth;
  }
  const std::string qualifier = " const";
  if (out.size() > qualifier.size() &&
      out.compare(out.size() - qualifier.size(), qualifier.size(), qualifier) == 0) {
    out.resize(out.size() - qualifier.size());
  }
  const std::size_t space = out.rfind(' ');
  return space == std::string::npos ? out : out.substr(space + 1);
}

// ---- Sections ----------------------------------------------------------------------------------
std::string met(bool ok) {
  return ok ? "**met**" : "**missed**";
}

struct BatchResult {
  std::string name;
  double speedup = 0.0;
  double batch_items = 0.0, single_items = 0.0;
};

// batch/<scalar>/N<lanes>... against singles/<scalar>/N<lanes>... (the same name after the prefix)
// from Google Benchmark's JSON output: the median aggregate when the run had repetitions, else the
// single run. (Its CSV reporter refuses benchmarks with differing counters.)
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

void section_targets(std::ostream& md, const Results& results,
                     const std::vector<BatchResult>& batches, bool bench_step_ran,
                     const Profile& profile) {
  md << "## Targets\n\n";
  Table t;
  t.header = {"target", "measured", "verdict"};

  // 1. Cost of stick-slip / exact / double.
  const Row* headline =
      results.find(kHeadlineScene, "stick-slip", "exact", "double", kHeadlineDtMs);
  std::vector<double> all_scenes;
  double worst = 0.0;
  std::string worst_scene;
  for (const Row& r : results.rows) {
    if (r.implementation == "stickslip" && r.model == "stick-slip" && r.integrator == "exact" &&
        r.scalar == "double" && same_dt(r.dt_ms, kHeadlineDtMs) && r.ns_median) {
      all_scenes.push_back(*r.ns_median);
      if (*r.ns_median > worst) {
        worst = *r.ns_median;
        worst_scene = r.scene;
      }
    }
  }
  if (headline && headline->ns_median) {
    const double got = *headline->ns_median;
    std::string measured = fmt::format(
        "**{} ns/sample** median on {} at 1 ms ({:.0f} repetitions: fastest {}, slowest {})",
        ns(got), kHeadlineScene, headline->repetitions.value_or(0),
        ns(headline->ns_min.value_or(0)), ns(headline->ns_max.value_or(0)));
    if (profile.steps > 0.0) {
      measured += fmt::format(", {:.0f} instructions/sample (callgrind, whole scene)",
                              profile.total / profile.steps);
    } else if (headline->ir_per_sample) {
      measured += fmt::format(", {:.0f} instructions/sample", *headline->ir_per_sample);
    }
    measured +=
        fmt::format("; over the {} Coulomb scenes at 1 ms: {}–{} ns, median {} (slowest {})",
                    all_scenes.size(), ns(*std::min_element(all_scenes.begin(), all_scenes.end())),
                    ns(worst), ns(median_of(all_scenes)), worst_scene);
    std::string verdict = met(got <= kTargetNsPerSample);
    if (got > kTargetNsPerSample) {
      verdict += fmt::format(" by {} ns ({:.0f} %); see *Where the time goes*",
                             ns(got - kTargetNsPerSample),
                             100.0 * (got - kTargetNsPerSample) / kTargetNsPerSample);
    }
    t.rows.push_back(
        {"stick-slip, exact, double, streaming (step + statistics, no I/O): <= 10 ns/sample median",
         measured, verdict});
  } else {
    t.rows.push_back({"stick-slip, exact, double: <= 10 ns/sample", "not in this run", "–"});
  }

  // 2. Accuracy at dt = 1 ms on the lorry-like scenes.
  double worst_tax = 0.0, worst_p = 0.0;
  std::string worst_tax_scene, worst_p_scene;
  int lorry_runs = 0;
  for (const Row& r : results.rows) {
    if (r.implementation != "stickslip" || r.kind != "lorry" || r.model != "stick-slip" ||
        r.integrator != "exact" || r.scalar != "double" || !same_dt(r.dt_ms, kHeadlineDtMs) ||
        !r.ok()) {
      continue;
    }
    ++lorry_runs;
    if (r.t_ax_rel_err && *r.t_ax_rel_err >= worst_tax) {
      worst_tax = *r.t_ax_rel_err;
      worst_tax_scene = r.scene;
    }
    if (r.p_abs_err && *r.p_abs_err >= worst_p) {
      worst_p = *r.p_abs_err;
      worst_p_scene = r.scene;
    }
  }
  if (headline && lorry_runs > 0) {
    t.rows.push_back(
        {"dt = 1 ms, lorry-like scene: T_ax within 0.1 % and p within 0.005 of the reference",
         fmt::format("{}: T_ax error {}, p error {}; worst over the {} lorry Coulomb scenes (K, "
                     "b): T_ax {} ({}), "
                     "p {} ({})",
                     kHeadlineScene, opt_sci(headline->t_ax_rel_err), opt_sci(headline->p_abs_err),
                     lorry_runs, sci(worst_tax), worst_tax_scene, sci(worst_p), worst_p_scene),
         met(worst_tax <= kTargetTaxRelErr && worst_p <= kTargetPAbsErr)});
  }

  // 3. Against the fastest Odeint peer at the same T_ax error.
  if (headline && headline->ok() && headline->t_ax_rel_err) {
    const double ours_err = *headline->t_ax_rel_err, ours_ns = *headline->ns_median;
    const Row *same = nullptr, *band = nullptr, *most_accurate = nullptr;
    for (const Row& r : results.rows) {
      if (r.implementation != "odeint" || r.scene != kHeadlineScene ||
          !same_dt(r.dt_ms, kHeadlineDtMs) || !r.ok() || !r.t_ax_rel_err || !r.ns_median) {
        continue;
      }
      if (*r.t_ax_rel_err <= ours_err && (!same || *r.ns_median < *same->ns_median)) same = &r;
      if (*r.t_ax_rel_err <= kTargetTaxRelErr && (!band || *r.ns_median < *band->ns_median))
        band = &r;
      if (!most_accurate || *r.t_ax_rel_err < *most_accurate->t_ax_rel_err) most_accurate = &r;
    }
    std::string measured;
    double ratio = 0.0;
    if (same) {
      ratio = *same->ns_median / ours_ns;
      measured =
          fmt::format("fastest peer with a T_ax error <= ours ({}): {} at {} ns/sample -> **{}**",
                      sci(ours_err), same->configuration(), ns(*same->ns_median), times(ratio));
    } else if (most_accurate) {
      ratio = *most_accurate->ns_median / ours_ns;
      measured = fmt::format(
          "no peer reaches our T_ax error ({}); the most accurate, {} ({} ns/sample, error {}), is "
          "**{}** "
          "slower",
          sci(ours_err), most_accurate->configuration(), ns(*most_accurate->ns_median),
          opt_sci(most_accurate->t_ax_rel_err), times(ratio));
    }
    if (band) {
      measured += fmt::format("; the fastest peer inside the 0.1 % band is {} at {} ns/sample: {}",
                              band->configuration(), ns(*band->ns_median),
                              times(*band->ns_median / ours_ns));
    }
    std::string verdict =
        measured.empty() ? "not measured (no peer run)" : met(ratio >= kTargetPeerRatio);
    if (!measured.empty() && ratio < kTargetPeerRatio) {
      verdict += fmt::format(" ({} of 50x); see *Peers*", times(ratio));
    }
    t.rows.push_back(
        {fmt::format(">= 50x faster than the fastest Boost.Odeint peer that reaches the same T_ax "
                     "error ({}, 1 ms)",
                     kHeadlineScene),
         measured.empty() ? "–" : measured, verdict});
  }

  // 4. Batch mode (helper benchmark).
  if (!bench_step_ran) {
    t.rows.push_back({"batch mode >= 4x single-oscillator throughput",
                      "`stickslip_bench_step` was not built when this report ran", "not measured"});
  } else if (batches.empty()) {
    t.rows.push_back(
        {"batch mode >= 4x single-oscillator throughput",
         "`stickslip_bench_step` ran but has no batch/<scalar>/N<lanes> benchmark with a "
         "singles/<scalar>/N<lanes> partner (its output is below)",
         "not measured"});
  } else {
    std::string measured;
    double best = 0.0;
    for (const BatchResult& b : batches) {
      measured += fmt::format("{}{}: {}", measured.empty() ? "" : "; ", b.name, times(b.speedup));
      best = std::max(best, b.speedup);
    }
    t.rows.push_back(
        {"batch mode >= 4x single-oscillator throughput (items/s of batch/<scalar>/N over "
         "singles/<scalar>/N on the same inputs, `stickslip_bench_step` medians)",
         measured, met(best >= kTargetBatchSpeedup) + fmt::format(" (best {})", times(best))});
  }
  t.write(md);
}

// ---- Batch profile ------------------------------------------------------------------------------
struct BatchProfile {
  std::string name;          // e.g. batch/double/N8/own-inputs
  double lane_steps = 0.0;   // lane-steps of the profiled run (lane_steps counter x iterations)
  double total = 0.0;        // instructions inside run_batch / run_stream, callees included
  double common_path = 0.0;  // of which in the loop function itself (the inlined step + statistics)
  bool ok() const { return lane_steps > 0.0 && total > 0.0; }
};

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

// Why batch mode falls short of the 4x target, from callgrind counts of one run of each benchmark.
void section_batch_profile(std::ostream& md, const ReportRequest& request,
                           const std::vector<BatchResult>& batches) {
  if (request.batch_profile_dir.empty()) return;
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"batch/double/N8/own-inputs", "singles/double/N8/own-inputs"},
      {"batch/float/N16/own-inputs", "singles/float/N16/own-inputs"}};
  std::vector<std::pair<BatchProfile, BatchProfile>> profiles;
  for (const auto& [batch, single] : pairs) {
    BatchProfile b = read_batch_profile(request.batch_profile_dir, batch);
    BatchProfile s = read_batch_profile(request.batch_profile_dir, single);
    if (b.ok() && s.ok()) profiles.emplace_back(b, s);
  }
  md << "### Why the batch target is missed (callgrind)\n\n";
  if (profiles.empty()) {
    md << "The batch profile did not run (valgrind or the benchmark missing), so the miss is not "
          "profiled here.\n\n";
    return;
  }
  md << "One run of each benchmark under `valgrind --tool=callgrind --toggle-collect='*run_batch*' "
        "--toggle-collect='*run_stream*'`: instructions per lane-step inside the loop, split into "
        "the loop "
        "function itself (the inlined common path: whole step stuck or slipping, and the "
        "statistics) and "
        "everything it calls out of line (the event search: Taylor segment, bracketed Newton, the "
        "event "
        "lanes' redo by their single oscillator).\n\n"
        "| benchmark | instructions/lane-step | common path (inlined) | event path (out of line) "
        "|\n"
        "|---|---|---|---|\n";
  for (const auto& [b, s] : profiles) {
    for (const BatchProfile* p : {&b, &s}) {
      md << fmt::format("| {} | {:.1f} | {:.1f} | {:.1f} |\n", p->name, p->total / p->lane_steps,
                        p->common_path / p->lane_steps,
                        (p->total - p->common_path) / p->lane_steps);
    }
  }
  md << "\n";
  for (const auto& [b, s] : profiles) {
    const double b_common = b.common_path / b.lane_steps, s_common = s.common_path / s.lane_steps;
    const double b_event = (b.total - b.common_path) / b.lane_steps;
    const double s_total = s.total / s.lane_steps;
    const double amdahl = b_event > 0.0 ? s_total / b_event : 0.0;
    md << fmt::format(
        "- **{}**: the event path costs {:.1f} instructions per lane-step in the batch and {:.1f} "
        "in the "
        "singles: the batch redoes an event lane with the single oscillator's own code, so this "
        "part "
        "cannot shrink, and with it alone the batch could be at most {:.1f}x the singles' {:.1f} "
        "instructions/lane-step even if its common path were free (Amdahl). The vectorised common "
        "path "
        "takes {:.1f} instructions per lane-step against the scalar path's {:.1f} (ratio {:.2f}): "
        "it computes "
        "both candidates (a whole step stuck and a whole step slipping) for every lane and selects "
        "by "
        "bit masks, and the default x86-64 target (SSE2) holds only {} {}s per vector.\n",
        b.name, b_event, (s.total - s.common_path) / s.lane_steps, amdahl, s_total, b_common,
        s_common, s_common > 0.0 ? b_common / s_common : 0.0,
        b.name.find("/float/") != std::string::npos ? 4 : 2,
        b.name.find("/float/") != std::string::npos ? "float" : "double");
  }
  const std::vector<BatchResult> avx2 = batch_speedups(read_text(request.bench_step_avx2_json));
  if (!avx2.empty()) {
    std::string measured;
    double best = 0.0;
    for (const BatchResult& r : avx2) {
      measured += fmt::format("{}{}: {}", measured.empty() ? "" : "; ", r.name, times(r.speedup));
      best = std::max(best, r.speedup);
    }
    double best_default = 0.0;
    for (const BatchResult& r : batches) best_default = std::max(best_default, r.speedup);
    md << fmt::format(
        "- **Built for AVX2** (`-DSTICKSLIP_ARCH=x86-64-v3`: 4 doubles or 8 floats per vector, FMA "
        "contraction off), the same benchmarks in the same report run: {} (best {}{}).\n",
        measured, times(best),
        best_default > 0.0
            ? fmt::format(", against {} with the default target", times(best_default))
            : std::string());
  } else {
    md << "- The AVX2 build was not measured in this run (the CPU lacks AVX2/FMA or the build "
          "failed).\n";
  }
  md << "- **What would close it:** (1) a vectorised event search (the Taylor-segment root finder "
        "run "
        "across lanes under masks) so that the ~1 % event lane-steps no longer drop to scalar code "
        "— "
        "without it the event path alone caps the ratio as computed above; (2) one candidate per "
        "lane "
        "instead of two (branch-free formulation of stuck and slipping as one affine map with "
        "per-lane coefficients); (3) wider vectors (AVX2/AVX-512 builds) for what remains. None of "
        "these "
        "changes the results, which the batch tests pin bit for bit to the single oscillator.\n\n";
}

void section_recommendation(std::ostream& md, const Results& results) {
  md << "## Recommendation: for this accuracy at this dt use ...\n\n"
        "For an accuracy band (relative error of T_ax against the physics of the scene) and the dt "
        "the "
        "input arrives at: the configuration that stays inside the band in **every** scene of the "
        "kind "
        "(all excitations, K and b of this run) at the lowest worst-case median ns/sample; costs "
        "within "
        "10 % count as a tie (timing noise), and the tie goes to the more accurate one. A "
        "configuration "
        "refused or unstable in any of those scenes does not qualify. The cell gives the "
        "worst-case cost "
        "and the worst-case T_ax error; '–': nothing qualifies.\n\n";
  struct Spec {
    const char* title;
    const char* friction;
    bool need_p;
  };
  const Spec specs[] = {
      {"Coulomb friction (F_fs = F_fk): models signum, smooth-*, stick-slip", "coulomb", false},
      {"Coulomb friction, and p within 0.005 too (only models with a stuck state can)", "coulomb",
       true},
      {"Stribeck friction (F_fs = 1.3 F_fk, v_S = 0.01 m/s): model stribeck", "stribeck", false},
      {"No friction: model linear", "none", false},
  };
  for (const Spec& spec : specs) {
    struct Aggregate {
      double err = 0.0, p_err = 0.0, cost = 0.0;
      bool ok = true, has_p = true;
      int scenes = 0;
    };
    std::map<std::string, std::map<double, Aggregate>> by_config;
    std::set<std::string> scenes;
    for (const Row& r : results.rows) {
      if (r.implementation != "stickslip" || r.friction != spec.friction) continue;
      scenes.insert(r.scene);
      Aggregate& a = by_config[r.configuration()][r.dt_ms];
      ++a.scenes;
      if (!r.ok() || !r.t_ax_rel_err || !r.ns_median) {
        a.ok = false;
        continue;
      }
      a.err = std::max(a.err, *r.t_ax_rel_err);
      a.cost = std::max(a.cost, *r.ns_median);
      if (r.p_abs_err) {
        a.p_err = std::max(a.p_err, *r.p_abs_err);
      } else {
        a.has_p = false;
      }
    }
    if (scenes.empty()) continue;
    md << "### " << spec.title << "\n\n";
    Table t;
    t.header = {"T_ax error within"};
    for (const double dt : results.dts) t.header.push_back("dt = " + dt_label(dt));
    for (const double band : kBands) {
      std::vector<std::string> row{percent(band)};
      for (const double dt : results.dts) {
        std::vector<std::pair<std::string, Aggregate>> candidates;
        double cheapest = std::numeric_limits<double>::infinity();
        for (const auto& [config, per_dt] : by_config) {
          const auto found = per_dt.find(dt);
          if (found == per_dt.end()) continue;
          const Aggregate& a = found->second;
          if (!a.ok || a.scenes != static_cast<int>(scenes.size()) || a.err > band) continue;
          if (spec.need_p && (!a.has_p || a.p_err > kTargetPAbsErr)) continue;
          candidates.emplace_back(config, a);
          cheapest = std::min(cheapest, a.cost);
        }
        const std::pair<std::string, Aggregate>* pick = nullptr;
        for (const auto& candidate : candidates) {
          if (candidate.second.cost > kCostTie * cheapest) continue;
          if (!pick || candidate.second.err < pick->second.err) pick = &candidate;
        }
        row.push_back(pick ? fmt::format("{} ({} ns, {})", pick->first, ns(pick->second.cost),
                                         sci(pick->second.err))
                           : "–");
      }
      t.rows.push_back(row);
    }
    t.write(md);
  }
}

void section_peers(std::ostream& md, const Results& results, const Profile& profile) {
  md << "## Peers: Boost.Odeint, side by side\n\n"
        "The same Coulomb scenes, sampled input, reference, streaming loop and statistics, solved "
        "the way a "
        "user would without this library (double, `std::array<double, 2>` state, first-order-hold "
        "input):\n\n"
        "- `odeint-rk4`: `runge_kutta4`, one step per sample, on the smoothed signum (tanh, c = "
        "1000).\n"
        "- `odeint-dopri5 tol T`: `make_controlled(T, T, runge_kutta_dopri5)` stepped with "
        "`try_step` to the "
        "end of each sample interval (the input has a kink at every sample; the proposed step size "
        "carries "
        "over), same model.\n"
        "- `odeint-dopri5-events tol T`: stick-slip the straightforward way: controlled dopri5 "
        "while slipping; "
        "after each accepted step a sign change of v_r is bisected (re-integrating from the step's "
        "start "
        "with a plain dopri5 step) down to 1e-3 s x T; there it sticks if |F_L| <= F_fs, else "
        "reverses; while "
        "stuck, |F_L| = F_fs is bisected in time.\n\n"
        "Ratio = the peer's median ns/sample over that of our fastest configuration (any model, "
        "integrator, "
        "scalar) whose T_ax error is at most the peer's, same scene and dt.\n\n";
  md << "### Lorry-like scenes at dt = 1 ms\n\n";
  Table t;
  t.header = {"scene",
              "peer",
              "ns/sample",
              "T_ax error",
              "p error",
              "a_x history error",
              "our fastest at <= that T_ax error",
              "ratio"};
  for (const Row& r : results.rows) {
    if (r.implementation != "odeint" || r.kind != "lorry" || !same_dt(r.dt_ms, kHeadlineDtMs))
      continue;
    if (!r.ok()) {
      t.rows.push_back({r.scene, r.configuration(), r.status, "–", "–", "–", "–", "–"});
      continue;
    }
    const Row* ours = results.fastest_ours(r.scene, r.dt_ms, *r.t_ax_rel_err);
    t.rows.push_back(
        {r.scene, r.configuration(), ns(*r.ns_median), opt_sci(r.t_ax_rel_err),
         opt_sci(r.p_abs_err), opt_sci(r.a_x_rms_err_rel),
         ours ? fmt::format("{} ({} ns)", ours->configuration(), ns(*ours->ns_median)) : "none",
         ours ? times(*r.ns_median / *ours->ns_median) : "–"});
  }
  t.write(md);

  md << "### All Coulomb scenes and dt\n\n";
  struct Summary {
    std::vector<double> ratios, costs;
    int runs = 0, failed = 0, unmatched = 0;
  };
  std::map<std::string, Summary> summaries;
  std::vector<std::string> order;
  for (const Row& r : results.rows) {
    if (r.implementation != "odeint") continue;
    const std::string config = r.configuration();
    if (!summaries.count(config)) order.push_back(config);
    Summary& s = summaries[config];
    ++s.runs;
    if (!r.ok()) {
      ++s.failed;
      continue;
    }
    s.costs.push_back(*r.ns_median);
    const Row* ours = results.fastest_ours(r.scene, r.dt_ms, *r.t_ax_rel_err);
    if (ours) {
      s.ratios.push_back(*r.ns_median / *ours->ns_median);
    } else {
      ++s.unmatched;
    }
  }
  Table all;
  all.header = {"peer",          "runs", "unstable", "ns/sample (median of runs)",
                "ratio: median", "min",  "max",      "runs none of ours matches"};
  for (const std::string& config : order) {
    const Summary& s = summaries[config];
    const bool any = !s.ratios.empty();
    all.rows.push_back({config, std::to_string(s.runs), std::to_string(s.failed),
                        s.costs.empty() ? "–" : ns(median_of(s.costs)),
                        any ? times(median_of(s.ratios)) : "–",
                        any ? times(*std::min_element(s.ratios.begin(), s.ratios.end())) : "–",
                        any ? times(*std::max_element(s.ratios.begin(), s.ratios.end())) : "–",
                        std::to_string(s.unmatched)});
  }
  all.write(md);

  // The 50x target against the fastest peer that is as accurate: why it is missed, if it is.
  const Row* ours = results.find(kHeadlineScene, "stick-slip", "exact", "double", kHeadlineDtMs);
  const Row* fastest = nullptr;  // the fastest peer inside the target's accuracy band
  for (const Row& r : results.rows) {
    if (r.implementation == "odeint" && r.scene == kHeadlineScene &&
        same_dt(r.dt_ms, kHeadlineDtMs) && r.ok() && r.t_ax_rel_err &&
        *r.t_ax_rel_err <= kTargetTaxRelErr && (!fastest || *r.ns_median < *fastest->ns_median)) {
      fastest = &r;
    }
  }
  if (ours && ours->ns_median && fastest &&
      *fastest->ns_median / *ours->ns_median < kTargetPeerRatio) {
    const double needed_ns = *fastest->ns_median / kTargetPeerRatio;
    md << fmt::format(
        "**Why the 50x target is missed.** On {} at 1 ms the fastest peer inside the 0.1 % band, "
        "{}, costs {} "
        "ns/sample: the event peer integrates only while slipping (the input is smooth inside a "
        "sample "
        "interval, so a loose tolerance takes few steps, clipped to the interval; a stuck sample "
        "is one "
        "comparison of |F_L| with F_fs) and needs no smoothing. 50x would mean {:.1f} ns/sample "
        "for us, "
        "against {} measured",
        kHeadlineScene, fastest->configuration(), ns(*fastest->ns_median), needed_ns,
        ns(*ours->ns_median));
    if (profile.steps > 0.0) {
      double statistics = 0.0;
      for (const auto& [where, ir] : profile.lines) {
        if (repository_path(where.first).find("statistics") != std::string::npos) statistics += ir;
      }
      const double per_ns = profile.total / profile.steps / *ours->ns_median;
      md << fmt::format(
          "; at the measured {:.1f} instructions per ns that is about {:.0f} instructions/sample, "
          "while the "
          "running statistics alone take {:.0f} and the loop {:.0f}",
          per_ns, needed_ns * per_ns, statistics / profile.steps, profile.total / profile.steps);
    }
    md << ". Against this peer the target is out of reach of any per-sample streaming step; "
          "against the "
          "peers a user gets with the smoothed signum (rk4, dopri5: the table above) the ratio is "
          "larger, and "
          "those peers carry the smoothing's model error, which no tolerance removes.\n\n";
  }
}

void section_headline_table(std::ostream& md, const Results& results) {
  md << fmt::format("## Every configuration on {} at dt = 1 ms\n\n", kHeadlineScene);
  md << "Errors against the physics of the scene (event-driven stick-slip, F_fs = F_fk) and "
        "against the "
        "model's own tight solution (solver error; different from the former only for the smoothed "
        "laws). "
        "History errors are RMS(difference)/RMS(reference). p comes only from models with a stuck "
        "state.\n\n";
  Table t;
  t.header = {"configuration", "status",      "ns/sample",   "instr/sample", "T_ax error",
              "p error",       "a_x history", "x_r history", "solver: T_ax", "solver: a_x history"};
  for (const Row& r : results.rows) {
    if (r.scene != kHeadlineScene || !same_dt(r.dt_ms, kHeadlineDtMs)) continue;
    t.rows.push_back({r.configuration(), r.status, r.ns_median ? ns(*r.ns_median) : "–",
                      r.ir_per_sample ? fmt::format("{:.0f}", *r.ir_per_sample) : "–",
                      opt_sci(r.t_ax_rel_err), opt_sci(r.p_abs_err), opt_sci(r.a_x_rms_err_rel),
                      opt_sci(r.x_r_rms_err_rel), opt_sci(r.solver_t_ax_rel_err),
                      opt_sci(r.solver_a_x_rms_err_rel)});
  }
  t.write(md);
}

void section_model_vs_solver(std::ostream& md, const Results& results) {
  md << "## Model error and solver error\n\n"
        "For the smoothed laws on the lorry-like scenes (b = 504, double, dt = 1 ms): relative "
        "T_ax error "
        "vs physics (stick-slip) / vs the same law solved tightly. The first is what a user gets; "
        "the "
        "second is what the integrator adds. Where the second is far below the first, no "
        "integrator and no "
        "smaller dt helps: the model itself is off.\n\n";
  std::vector<std::string> integrators;
  std::map<std::pair<std::string, std::string>, std::map<std::string, std::string>> cells;
  std::vector<std::pair<std::string, std::string>> order;
  for (const Row& r : results.rows) {
    if (r.implementation != "stickslip" || r.kind != "lorry" || r.scalar != "double" ||
        r.damping_ns_per_m != 504.0 || !same_dt(r.dt_ms, kHeadlineDtMs) ||
        r.model.rfind("smooth", 0) != 0) {
      continue;
    }
    const auto key = std::make_pair(r.scene, r.model);
    if (!cells.count(key)) order.push_back(key);
    if (std::find(integrators.begin(), integrators.end(), r.integrator) == integrators.end()) {
      integrators.push_back(r.integrator);
    }
    cells[key][r.integrator] =
        r.ok() ? opt_sci(r.t_ax_rel_err) + " / " + opt_sci(r.solver_t_ax_rel_err) : r.status;
  }
  if (order.empty()) return;
  Table t;
  t.header = {"scene", "law"};
  for (const std::string& integrator : integrators) t.header.push_back(integrator);
  for (const auto& key : order) {
    std::vector<std::string> row{key.first, key.second};
    for (const std::string& integrator : integrators) {
      const auto found = cells[key].find(integrator);
      row.push_back(found == cells[key].end() ? "–" : found->second);
    }
    t.rows.push_back(row);
  }
  t.write(md);
}

void section_scene_summary(std::ostream& md, const Results& results) {
  md << "## Per scene: the cheapest configuration per accuracy band\n\n"
        "If the dt can be chosen: over every dt of the run, our configuration inside the band at "
        "the lowest "
        "cost per simulated second (median ns/sample / dt). Cell: `model/integrator/scalar @ dt: "
        "ns/sample "
        "(µs per simulated s)`. Every row is in the CSV.\n\n";
  Table t;
  t.header = {"scene", "T_ax (ref, 1 ms)", "p (ref, 1 ms)"};
  for (const double band : kBands) t.header.push_back("within " + percent(band));
  for (const std::string& scene : results.scenes) {
    const Row* any = nullptr;
    for (const Row& r : results.rows) {
      if (r.scene == scene && same_dt(r.dt_ms, kHeadlineDtMs)) {
        any = &r;
        break;
      }
    }
    if (!any) any = results.first_of_scene(scene);
    std::vector<std::string> row{scene,
                                 any && any->t_ax_ref ? fmt::format("{:.4f}", *any->t_ax_ref) : "–",
                                 any && any->p_ref ? fmt::format("{:.3f}", *any->p_ref) : "–"};
    for (const double band : kBands) {
      const Row* best = nullptr;
      for (const Row& r : results.rows) {
        if (r.implementation != "stickslip" || r.scene != scene || !r.ok() || !r.t_ax_rel_err ||
            !r.ns_median || *r.t_ax_rel_err > band) {
          continue;
        }
        if (!best || *r.ns_median / r.dt_ms < *best->ns_median / best->dt_ms) best = &r;
      }
      row.push_back(best ? fmt::format("{} @ {}: {} ({:.1f})", best->configuration(),
                                       dt_label(best->dt_ms), ns(*best->ns_median),
                                       *best->ns_median / best->dt_ms)
                         : "–");
    }
    t.rows.push_back(row);
  }
  t.write(md);
}

void section_refusals(std::ostream& md, const Results& results) {
  md << "## Refused and unstable combinations\n\n"
        "`refused: <parameter>`: `configure()` refused the combination (its message names the "
        "parameter and "
        "the limit); `unstable`: it ran and blew up. Neither gets error figures.\n\n";
  struct Group {
    std::set<double> dts;
    std::set<std::string> scenes, scalars;
    std::string example;
  };
  std::map<std::pair<std::string, std::string>, Group> groups;
  for (const Row& r : results.rows) {
    if (r.ok()) continue;
    const std::string config =
        r.implementation == "odeint" ? r.configuration() : r.model + "/" + r.integrator;
    Group& g = groups[{r.status, config}];
    g.dts.insert(r.dt_ms);
    g.scenes.insert(r.scene);
    g.scalars.insert(r.scalar);
    if (g.example.empty()) g.example = r.note;
  }
  // Runs that are ok but carry a warning (e.g. the core's event budget exhausted in some step).
  Table warnings;
  warnings.header = {"scene", "configuration", "dt (ms)", "warning"};
  for (const Row& r : results.rows) {
    if (r.ok() && !r.note.empty()) {
      warnings.rows.push_back({r.scene, r.configuration(), fmt::format("{:g}", r.dt_ms), r.note});
    }
  }
  if (!warnings.rows.empty()) {
    md << "Runs that are ok but carry a warning:\n\n";
    warnings.write(md);
  }
  if (groups.empty()) {
    md << "No combination was refused or unstable in this run.\n\n";
    return;
  }
  Table t;
  t.header = {"status", "configuration", "scalar", "dt (ms)", "scenes", "message (first case)"};
  for (const auto& [key, g] : groups) {
    std::string dts, scalars;
    for (const double dt : g.dts) dts += (dts.empty() ? "" : ", ") + fmt::format("{:g}", dt);
    for (const std::string& s : g.scalars) scalars += (scalars.empty() ? "" : ", ") + s;
    t.rows.push_back(
        {key.first, key.second, scalars, dts, std::to_string(g.scenes.size()), g.example});
  }
  t.write(md);
}

void section_profile(std::ostream& md, const Results& results, const Profile& profile) {
  md << "## Where the time goes (callgrind)\n\n";
  if (profile.total <= 0.0 || profile.steps <= 0.0) {
    md << "No profile was recorded in this run.\n\n";
    return;
  }
  const Row* headline =
      results.find(kHeadlineScene, "stick-slip", "exact", "double", kHeadlineDtMs);
  const double per_step = profile.total / profile.steps;
  md << fmt::format(
      "The streaming loop of stick-slip / exact / double on {} at 1 ms over the whole scene "
      "({:.0f} steps) "
      "under callgrind: **{:.1f} instructions/sample**",
      kHeadlineScene, profile.steps, per_step);
  if (headline && headline->ns_median) {
    md << fmt::format(" in {} ns/sample, {:.1f} instructions per ns", ns(*headline->ns_median),
                      per_step / *headline->ns_median);
  }
  if (headline && headline->events) {
    md << fmt::format("; the scene has {:.1f} stick/slip events per 1000 steps",
                      1000.0 * *headline->events / static_cast<double>(headline->steps));
  }
  md << ".\n\nSelf cost per function (inlined code counts where it was inlined):\n\n";
  std::vector<std::pair<double, std::string>> functions;
  for (const auto& [name, ir] : profile.functions) functions.emplace_back(ir, name);
  std::sort(functions.rbegin(), functions.rend());
  Table f;
  f.header = {"instructions/sample", "share", "function"};
  for (std::size_t i = 0; i < functions.size() && i < 6 && functions[i].first > 0.0; ++i) {
    f.rows.push_back({fmt::format("{:.1f}", functions[i].first / profile.steps),
                      fmt::format("{:.1f} %", 100.0 * functions[i].first / profile.total),
                      "`" + short_function(functions[i].second) + "`"});
  }
  f.write(md);
  md << "The source lines that execute the most instructions (self cost, inlined code at its own "
        "line):\n\n";
  std::vector<std::pair<double, std::pair<std::string, long>>> hot;
  for (const auto& [where, ir] : profile.lines) hot.emplace_back(ir, where);
  std::sort(hot.rbegin(), hot.rend());
  Table t;
  t.header = {"instructions/sample", "share", "where", "code"};
  std::map<std::string, double> by_file;
  for (const auto& [where, ir] : profile.lines) by_file[repository_path(where.first)] += ir;
  for (std::size_t i = 0; i < hot.size() && i < 16; ++i) {
    const auto& [ir, where] = hot[i];
    t.rows.push_back({fmt::format("{:.2f}", ir / profile.steps),
                      fmt::format("{:.1f} %", 100.0 * ir / profile.total),
                      fmt::format("{}:{}", repository_path(where.first), where.second),
                      "`" + source_line(where.first, where.second) + "`"});
  }
  t.write(md);
  md << "By source file:";
  std::vector<std::pair<double, std::string>> files;
  for (const auto& [file, ir] : by_file) files.emplace_back(ir, file);
  std::sort(files.rbegin(), files.rend());
  for (std::size_t i = 0; i < files.size() && i < 6; ++i) {
    md << fmt::format("{} `{}` {:.1f} ({:.0f} %)", i ? ";" : "", files[i].second,
                      files[i].first / profile.steps, 100.0 * files[i].first / profile.total);
  }
  md << " instructions/sample.\n\n";
  if (headline && headline->ns_median && *headline->ns_median > kTargetNsPerSample) {
    // Which part of a sample is the unavoidable work and which is the event machinery, by the
    // source text of the lines: the affine map, the running statistics, the non-finite guards.
    double affine = 0.0, statistics = 0.0, guards = 0.0;
    for (const auto& [where, ir] : profile.lines) {
      const std::string file = repository_path(where.first);
      const std::string code = source_line(where.first, where.second);
      if (file.find("statistics") != std::string::npos) {
        statistics += ir;
      } else if (code.find("is_finite") != std::string::npos ||
                 code.find("isfinite") != std::string::npos ||
                 code.find("guard_state") != std::string::npos ||
                 code.find("infinity") != std::string::npos) {
        guards += ir;
      } else if (code.find("m.xx *") != std::string::npos ||
                 code.find("m.vx *") != std::string::npos) {
        affine += ir;
      }
    }
    const double rest = profile.total - affine - statistics - guards;
    const double ipc_ns = per_step / *headline->ns_median;  // instructions per ns as measured
    const double needed = kTargetNsPerSample * ipc_ns;
    const double essential = (affine + statistics + guards) / profile.steps;
    double search = 0.0;  // the in-step event search, when it is a function of its own
    for (const auto& [name, ir] : profile.functions) {
      if (short_function(name).find("::slip") != std::string::npos) search += ir;
    }
    md << fmt::format(
        "**Why the target is missed, and what would close it.** At the measured {:.1f} "
        "instructions per ns, "
        "10 ns/sample allows about {:.0f} instructions/sample; the loop executes {:.0f}, {:.0f} % "
        "too many "
        "(or it would need a higher IPC, which the dependent chain x -> x' of the affine map "
        "limits). Of "
        "those, the affine map of the step (the lines `x' = m.xx x + ...`, `v' = m.vx x + ...`) is "
        "{:.1f}, "
        "the running statistics {:.1f} and the non-finite guards {:.1f} instructions/sample: "
        "{:.0f} "
        "together, the work every sample needs. The other {:.0f} instructions/sample ({:.0f} %) "
        "are the "
        "friction logic around the map (first-order-hold input and relative acceleration at block "
        "ends, "
        "sign-change and dip tests, mode switches; the lines above).",
        ipc_ns, needed, per_step, 100.0 * (per_step / needed - 1.0), affine / profile.steps,
        statistics / profile.steps, guards / profile.steps, essential, rest / profile.steps,
        100.0 * rest / profile.total);
    if (search > 0.3 * profile.total && headline->events) {
      md << fmt::format(
          " The in-step event search (`Oscillator::slip`) alone is {:.0f} instructions/sample "
          "({:.0f} %), and it "
          "runs on every slipping step although only {:.1f} in 1000 steps hold an event. The lever "
          "is a "
          "whole-step fast path: advance a slipping step with the one precomputed map, show with a "
          "cheap "
          "bound that v_r cannot have changed sign inside it, and enter the dyadic search only "
          "when it may "
          "have. That would bring the loop towards the {:.0f} instructions of map, statistics and "
          "guards "
          "(about {:.0f} ns at the same IPC).",
          search / profile.steps, 100.0 * search / profile.total,
          1000.0 * *headline->events / static_cast<double>(headline->steps), essential,
          essential / ipc_ns);
    }
    md << "\n\n";
  }
}

}  // namespace

void write_report(const ReportRequest& request) {
  Results results(read_rows(request.results_csv));
  if (results.rows.empty()) throw host::HostError(request.results_csv + ": no results");
  const auto facts = read_facts(request.machine_file);
  const Profile profile = parse_callgrind_dump(request.profile_dump);
  const std::string bench_text = read_text(request.bench_step_text);
  const std::vector<BatchResult> batches = batch_speedups(read_text(request.bench_step_json));

  std::error_code error;
  std::filesystem::create_directories(request.plot_dir, error);
  if (error) throw host::HostError(request.plot_dir + ": " + error.message());
  std::vector<std::pair<std::string, std::string>> figures;
  for (const char* scene : {"lorry-K0.8-b504", "lorry-K0.2-b504", "lorry-K1.5-b504",
                            "lorry-K0.8-b0", "wideband-K0.8-b504", "harmonic-K0.8-b504"}) {
    if (results.has_scene(scene)) figures.emplace_back(scene, fmt::format("pareto-{}.png", scene));
  }
  write_gnuplot(results, request.plot_dir, figures);

  const std::string temporary = request.output_md + ".partial";
  std::ofstream md(temporary);
  if (!md) throw host::HostError(temporary + ": cannot open for writing");

  md << "# Performance: speed vs accuracy\n\n"
        "<!-- Generated by tools/performance-report.sh (stickslip_tradeoff report): do not edit, "
        "re-run. -->\n\n";
  md << fmt::format("Measured {} on commit {}.\n\n", fact(facts, "date"), fact(facts, "commit"));

  md << "## Reproduce\n\n```sh\n" << request.command << "\n```\n\n";
  md << "One command: installs what is missing (`tools/install-deps.sh --report`: gnuplot-nox, "
        "valgrind), "
        "configures and builds the `release` preset, counts instructions under callgrind, runs the "
        "harness "
        "(`stickslip_tradeoff run`), profiles the headline configuration, runs "
        "`stickslip_bench_step` if it "
        "is built, writes this file and draws the plots.";
  if (request.elapsed_s > 0.0) {
    md << fmt::format(
        " It took **{:.0f} min {:02.0f} s** on the machine below (up to writing this file).",
        std::floor(request.elapsed_s / 60.0), std::fmod(request.elapsed_s, 60.0));
  }
  md << "\n\n";

  md << "## Machine and build\n\n";
  Table machine;
  machine.header = {"", ""};
  machine.rows = {
      {"CPU", fact(facts, "cpu")},
      {"cores", fact(facts, "cores")},
      {"OS", fact(facts, "os")},
      {"compiler", fact(facts, "compiler")},
      {"build", "CMake `release` preset: " + fact(facts, "build type") + ", flags `" +
                    fact(facts, "flags") + "`"},
      {"reference", fact(facts, "reference")},
      {"load average (1 min) at the start / end of the timed run",
       fact(facts, "load before") + " / " + fact(facts, "load after") +
           " (the harness itself adds 1 on 2 cores; more means other processes shared the "
           "machine and disturbed the timings: the CSV keeps each run's fastest and slowest "
           "repetition too)"}};
  machine.write(md);

  const Row& first = results.rows.front();
  md << "## Method\n\n";
  // What this run covered, from the rows themselves (the command line may have narrowed it).
  const auto distinct = [&](auto member, auto keep) {
    std::set<std::string> out;
    for (const Row& r : results.rows) {
      if (keep(r)) out.insert(member(r));
    }
    std::string text;
    for (const std::string& item : out) text += (text.empty() ? "" : ", ") + item;
    return text.empty() ? std::string("none") : text;
  };
  const auto distinct_numbers = [&](auto member, auto keep) {
    std::set<double> out;
    for (const Row& r : results.rows) {
      if (keep(r)) out.insert(member(r));
    }
    std::string text;
    for (const double item : out) text += (text.empty() ? "" : ", ") + fmt::format("{:g}", item);
    return text.empty() ? std::string("none") : text;
  };
  const auto any = [](const Row&) { return true; };
  md << fmt::format(
      "- **Scenes** ({}): excitations {} (wideband 0.5–20 Hz; lorry-like; harmonic at 1.8 Hz, the "
      "resonance "
      "is 1.82 Hz), RMS a0u = 0.35 m/s^2, {:g} s each; m = 88.4 kg, k = 11500 N/m, b in {{{}}} N "
      "s/m. "
      "Coulomb scenes: F_fs = F_fk from K = 4 F_fk/(pi sqrt(2) m a0u), K in {{{}}}; Stribeck "
      "scenes: "
      "F_fs = 1.3 F_fk, v_S = 0.01 m/s; frictionless scenes for the linear model. Names: "
      "`<excitation>-K<K>-b<b>`, `<excitation>-stribeck-K<K>-b<b>`, `<excitation>-linear-b<b>`.\n",
      results.scenes.size(), distinct([](const Row& r) { return r.kind; }, any), first.duration_s,
      distinct_numbers([](const Row& r) { return r.damping_ns_per_m; }, any),
      distinct_numbers([](const Row& r) { return r.den_hartog_k; },
                       [](const Row& r) { return r.friction != "none"; }));
  md << fmt::format(
      "- **Runs**: models {} (smooth-* with c = 1000 s/m; smooth-atan at dt {{{}}} ms only); "
      "integrators {}; "
      "scalars {}; dt {{{}}} ms; Boost.Odeint peers {}.\n",
      distinct([](const Row& r) { return r.model; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct_numbers([](const Row& r) { return r.dt_ms; },
                       [](const Row& r) { return r.model == "smooth-atan"; }),
      distinct([](const Row& r) { return r.integrator; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct([](const Row& r) { return r.scalar; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct_numbers([](const Row& r) { return r.dt_ms; }, any),
      distinct([](const Row& r) { return r.configuration(); },
               [](const Row& r) { return r.implementation == "odeint"; }));
  md << "- **Input**: each excitation is generated once at 0.05 ms "
        "(`stickslip::host::generate_signal`, seed 1); "
        "the input at dt is every (dt/0.05 ms)-th sample, so a run and its reference see the same "
        "samples "
        "(first-order hold between them; float runs get them rounded to float).\n";
  md << "- **Reference**: `" << fact(facts, "reference")
     << "`, on the same sampled input at the same dt. *Error vs physics* compares with the scene's "
        "physically "
        "correct reference (stick-slip with F_fs = F_fk for signum, smooth and stick-slip — the "
        "exact Filippov "
        "solution of signum is stick-slip; Stribeck; linear); *solver error* with the model's own "
        "reference.\n";
  md << "- **Errors**: relative error of T_ax = RMS(a_x)/RMS(a_u), i.e. of RMS a_x (same input; "
        "the run's own "
        "running statistics, float runs in float); absolute error of the stick probability p "
        "(stuck time / "
        "total time; models with a stuck state only); RMS of the a_x and x_r history differences, "
        "relative "
        "to the reference's RMS here (absolute in the CSV).\n";
  md << "- **Cost**: the streaming loop only — `reset`, then `step()` and "
        "`RunningStatistics::add_sample/"
        "add_step` per sample, no I/O, no allocation, the model dispatched once outside the loop "
        "(the trace "
        "for the errors comes from a separate, untimed pass). A warm-up pass, then repetitions of "
        "at least "
        "2 ms each (whole passes over the input); the median ns per step is reported, the fastest "
        "and slowest "
        "repetitions are in the CSV.\n";
  md << fmt::format(
      "- **Instructions**: `perf stat -e instructions` is not supported on this machine. The "
      "harness runs "
      "once under `valgrind --tool=callgrind --collect-atstart=no` (`stickslip_tradeoff "
      "count-instructions`): "
      "each combination's loop runs over the first {} steps of its input between "
      "CALLGRIND_ZERO_STATS + "
      "CALLGRIND_TOGGLE_COLLECT and CALLGRIND_TOGGLE_COLLECT + "
      "CALLGRIND_DUMP_STATS_AT(\"<combination>#<steps>\"), "
      "and `run --instructions` reads the Ir totals from the dump files (our configurations; the "
      "peers are "
      "timed only). (START/STOP_INSTRUMENTATION with "
      "`--instr-atstart=no` gives the same counts but flushes the translation cache at every "
      "switch, which "
      "made the pass several times slower over thousands of combinations; `--collect-atstart=no` "
      "with "
      "START/STOP_INSTRUMENTATION alone counts nothing, collection stays off.)\n",
      fact(facts, "instruction steps"));
  md << "- **Status**: `refused: <parameter>` when `configure()` refuses, `unstable` when a run "
        "leaves any "
        "physical range (non-finite, |x_r| above 10x the reference's + 1 m, or RMS a_x above 100x "
        "the "
        "reference's + 10 m/s^2); neither gets error figures.\n\n";

  section_targets(md, results, batches, !bench_text.empty(), profile);

  md << "## Pareto plots\n\n";
  for (const auto& [scene, png] : figures) {
    md << fmt::format("![{}: error vs cost]({}/{})\n\n", scene, request.image_link, png);
  }
  md << "Along a curve dt runs from 0.1 ms to 10 ms; the cost per *sample* hardly depends on dt "
        "(the cost "
        "per simulated second does, by 1/dt), the error does.\n\n";

  section_recommendation(md, results);
  section_peers(md, results, profile);
  section_headline_table(md, results);
  section_model_vs_solver(md, results);
  section_scene_summary(md, results);
  section_refusals(md, results);
  section_profile(md, results, profile);

  md << "## Batch mode (stickslip_bench_step)\n\n";
  if (bench_text.empty()) {
    md << "`stickslip_bench_step` was not built when this report ran, so the batch target is not "
          "measured.\n\n";
  } else {
    // The medians only (the run has repetitions; mean, stddev and cv are in the JSON).
    std::istringstream lines(bench_text);
    std::string line, kept;
    while (std::getline(lines, line)) {
      if (line.find("_mean ") != std::string::npos || line.find("_stddev ") != std::string::npos ||
          line.find("_cv ") != std::string::npos) {
        continue;
      }
      kept += line + "\n";
    }
    md << "`stickslip_bench_step` (Google Benchmark, bench/step/) as this report ran it, median "
          "aggregates:\n\n```\n"
       << kept << "```\n\n";
    if (kept.find("Library was built as DEBUG") != std::string::npos) {
      md << "(Google Benchmark's warning \"Library was built as DEBUG\" is about Debian's "
            "libbenchmark "
            "itself, which only drives the loop; the timed code is the project's release "
            "build.)\n\n";
    }
  }
  section_batch_profile(md, request, batches);

  md << "## Full results\n\n";
  std::string columns;
  for (const std::string& name : column_names())
    columns += (columns.empty() ? "`" : ", `") + name + "`";
  md << fmt::format(
      "Every row of the run: [{}]({}) ({} rows). Columns: {}. Empty cells: not applicable (e.g. "
      "p for models without a stuck state, errors of refused runs).\n",
      std::filesystem::path(request.results_link).filename().string(), request.results_link,
      results.rows.size(), columns);
  md.close();
  if (!md) throw host::HostError(temporary + ": write failed");
  std::filesystem::rename(temporary, request.output_md, error);
  if (error) throw host::HostError(request.output_md + ": " + error.message());
}

}  // namespace stickslip::tradeoff
