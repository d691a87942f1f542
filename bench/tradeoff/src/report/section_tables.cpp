#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "report/sections.hpp"
#include "report/targets.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {

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

}  // namespace stickslip::tradeoff::report
