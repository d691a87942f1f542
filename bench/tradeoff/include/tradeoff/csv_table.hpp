// One row of the harness's results (a model or peer run at one scene, scalar and dt) and the CSV
// that holds them (docs/performance/results.csv). Missing values are empty cells, never NaN.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace stickslip::tradeoff {

struct Row {
  // The scene.
  std::string scene, kind, friction;
  double den_hartog_k = 0.0, damping_ns_per_m = 0.0, kinetic_friction_n = 0.0,
         static_friction_n = 0.0, duration_s = 0.0;
  // The run.
  std::string implementation;  // "stickslip" or "odeint"
  std::string model, integrator, scalar;
  std::optional<double> tolerance;  // peers with a controlled stepper
  double dt_ms = 0.0;
  std::uint64_t steps = 0;
  std::string status;  // "ok", "refused: <parameter>", "unstable"
  // Cost.
  std::optional<double> ns_median, ns_min, ns_max, repetitions, ir_per_sample;
  // Accuracy against the physically correct reference of the scene ("error vs physics").
  std::optional<double> t_ax, t_ax_ref, t_ax_rel_err, p, p_ref, p_abs_err;
  std::optional<double> a_x_rms_err, a_x_rms_err_rel, x_r_rms_err, x_r_rms_err_rel;
  // Against the same model's own reference ("solver error"; equal to the above unless the model
  // differs from the scene's physics, i.e. the smoothed laws).
  std::optional<double> solver_t_ax_rel_err, solver_a_x_rms_err_rel, solver_x_r_rms_err_rel;
  std::optional<double> events;
  std::string note;  // configure's message for refusals, the reason for "unstable", warnings

  bool ok() const { return status == "ok"; }
  // "stick-slip/exact/double" or "odeint-dopri5-events 1e-06".
  std::string configuration() const;
};

std::vector<std::string> column_names();
// One line of RFC 4180 CSV (quoted cells, doubled quotes) into its cells.
std::vector<std::string> split_csv_line(const std::string& line);
void write_header(std::ostream& out);
void write_row(std::ostream& out, const Row& row);
// Throws host::HostError ("FILE:LINE: ...") on a malformed file or a missing column.
std::vector<Row> read_rows(const std::string& path);

}  // namespace stickslip::tradeoff
