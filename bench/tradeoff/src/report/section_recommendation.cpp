#include <algorithm>
#include <limits>
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
namespace {

// One table of the recommendation: a kind of friction, and whether p must be within its target.
struct Spec {
  const char* title;
  const char* friction;
  bool need_p;
};

// A configuration at one dt over every scene of the kind: worst error and cost.
struct Aggregate {
  double err = 0.0, p_err = 0.0, cost = 0.0;
  bool ok = true, has_p = true;
  int scenes = 0;
};

using ByConfig = std::map<std::string, std::map<double, Aggregate>>;

ByConfig aggregate(const Results& results, const Spec& spec, std::set<std::string>& scenes) {
  ByConfig by_config;
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
  return by_config;
}

// The cheapest qualifying configuration at dt (ties to the more accurate), or "–".
std::string pick(const ByConfig& by_config, const Spec& spec, std::size_t scene_count, double band,
                 double dt) {
  std::vector<std::pair<std::string, Aggregate>> candidates;
  double cheapest = std::numeric_limits<double>::infinity();
  for (const auto& [config, per_dt] : by_config) {
    const auto found = per_dt.find(dt);
    if (found == per_dt.end()) continue;
    const Aggregate& a = found->second;
    if (!a.ok || a.scenes != static_cast<int>(scene_count) || a.err > band) continue;
    if (spec.need_p && (!a.has_p || a.p_err > kTargetPAbsErr)) continue;
    candidates.emplace_back(config, a);
    cheapest = std::min(cheapest, a.cost);
  }
  const std::pair<std::string, Aggregate>* chosen = nullptr;
  for (const auto& candidate : candidates) {
    if (candidate.second.cost > kCostTie * cheapest) continue;
    if (!chosen || candidate.second.err < chosen->second.err) chosen = &candidate;
  }
  return chosen ? fmt::format("{} ({} ns, {})", chosen->first, ns(chosen->second.cost),
                              sci(chosen->second.err))
                : "–";
}

}  // namespace

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
  const Spec specs[] = {
      {"Coulomb friction (F_fs = F_fk): models signum, smooth-*, stick-slip", "coulomb", false},
      {"Coulomb friction, and p within 0.005 too (only models with a stuck state can)", "coulomb",
       true},
      {"Stribeck friction (F_fs = 1.3 F_fk, v_S = 0.01 m/s): model stribeck", "stribeck", false},
      {"No friction: model linear", "none", false},
  };
  for (const Spec& spec : specs) {
    std::set<std::string> scenes;
    const ByConfig by_config = aggregate(results, spec, scenes);
    if (scenes.empty()) continue;
    md << "### " << spec.title << "\n\n";
    Table t;
    t.header = {"T_ax error within"};
    for (const double dt : results.dts) t.header.push_back("dt = " + dt_label(dt));
    for (const double band : kBands) {
      std::vector<std::string> row{percent(band)};
      for (const double dt : results.dts) {
        row.push_back(pick(by_config, spec, scenes.size(), band, dt));
      }
      t.rows.push_back(row);
    }
    t.write(md);
  }
}

}  // namespace stickslip::tradeoff::report
