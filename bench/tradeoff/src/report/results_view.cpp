#include "report/results_view.hpp"

#include <algorithm>
#include <set>

#include "report/text.hpp"

namespace stickslip::tradeoff::report {

Results::Results(std::vector<Row> all) : rows(std::move(all)) {
  std::set<double> dt_set;
  for (const Row& r : rows) {
    if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    dt_set.insert(r.dt_ms);
  }
  dts.assign(dt_set.begin(), dt_set.end());
}

bool Results::has_scene(const std::string& scene) const {
  return std::find(scenes.begin(), scenes.end(), scene) != scenes.end();
}

const Row* Results::find(const std::string& scene, const std::string& model,
                         const std::string& integrator, const std::string& scalar,
                         double dt_ms) const {
  for (const Row& r : rows) {
    if (r.implementation == "stickslip" && r.scene == scene && r.model == model &&
        r.integrator == integrator && r.scalar == scalar && same_dt(r.dt_ms, dt_ms)) {
      return &r;
    }
  }
  return nullptr;
}

const Row* Results::first_of_scene(const std::string& scene) const {
  for (const Row& r : rows) {
    if (r.scene == scene) return &r;
  }
  return nullptr;
}

const Row* Results::fastest_ours(const std::string& scene, double dt_ms, double limit) const {
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

}  // namespace stickslip::tradeoff::report
