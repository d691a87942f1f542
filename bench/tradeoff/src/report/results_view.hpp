// The run's rows as the report looks them up: by configuration, by scene, fastest within an error.
#pragma once

#include <string>
#include <vector>

#include "tradeoff/csv_table.hpp"

namespace stickslip::tradeoff::report {

struct Results {
  std::vector<Row> rows;
  std::vector<std::string> scenes;  // in CSV order
  std::vector<double> dts;          // sorted

  explicit Results(std::vector<Row> all);

  bool has_scene(const std::string& scene) const;
  // Our run of that configuration, or nullptr.
  const Row* find(const std::string& scene, const std::string& model, const std::string& integrator,
                  const std::string& scalar, double dt_ms) const;
  const Row* first_of_scene(const std::string& scene) const;
  // Our fastest ok run on (scene, dt) with a T_ax error of at most `limit`.
  const Row* fastest_ours(const std::string& scene, double dt_ms, double limit) const;
};

}  // namespace stickslip::tradeoff::report
