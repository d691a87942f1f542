// The stability map: every model x integrator x scalar type over a grid of Den Hartog's K, damping
// ratio, smoothing constant and dt, each cell classified as refused by configure() (with its
// message), stable, or unstable (with the criterion that fired). Unstable accepted cells are bugs.
//
// A cell runs two scenes from the same configuration:
//   free decay  x_r(0) = kFreeDecayX0, v_r = 0, a_u = 0: the seat is passive, so its mechanical
//               energy E = (k x_r^2 + m v_r^2)/2 may not grow. Explicit schemes oscillate in energy
//               within a step-size-dependent band, so "growth" is measured: the largest E over the
//               last third of the run above kEnergyGrowthBound times the largest E over the first
//               third, or any E above kEnergyCeiling times E(0).
//   lorry       the lorry-like cab floor (sim_host's generator, RMS 0.35 m/s^2, seed 1): a bounded
//               input that a passive seat answers with centimetres; |x_r| beyond kTravelBoundM is
//               divergence.
// In both: any NaN/Inf in the outputs, any step that exhausted the event budget, any restart by
// the non-finite guard.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"

namespace stickslip::reliability {

inline constexpr double kFreeDecayX0M = 0.05;
inline constexpr double kEnergyGrowthBound = 1.1;
inline constexpr double kEnergyCeiling = 2.0;
inline constexpr double kTravelBoundM = 1.0;
inline constexpr double kLorryRms = 0.35;      // m/s^2, the a0u of Den Hartog's K
inline constexpr double kStribeckRatio = 1.3;  // F_fs / F_fk for Stribeck (stick-slip: F_fs = F_fk)

struct MapGrid {
  std::vector<double> den_hartog_k;
  std::vector<double> damping_ratio;
  std::vector<double> smoothing_c;  // s/m, smooth laws only
  std::vector<double> dt_s;
  double lorry_duration_s = 20.0;
  double free_decay_duration_s = 5.0;
  std::uint64_t max_steps = 200000;  // per scene: caps the run at small dt
  bool in_float = true;
  bool in_double = true;
};

MapGrid full_grid();    // K 0..100, zeta 0..2, c 1..1e6, dt 1e-5..0.05 (the documented map)
MapGrid coarse_grid();  // a subset for CTest (< 60 s, also under the sanitizers)

enum class Verdict : std::uint8_t { refused, stable, unstable };
const char* verdict_name(Verdict verdict) noexcept;

struct Cell {
  OscillatorParams params;
  double den_hartog_k = 0.0;
  double damping_ratio = 0.0;
  bool in_float = false;
  Verdict verdict = Verdict::stable;
  std::string reason;  // configure()'s message, or the instability criterion that fired
};

// "smooth/tanh" for smoothed laws, else the model name.
std::string law_label(const OscillatorParams& params);
std::string describe(const Cell& cell);

// The lorry-like input at dt_s over min(duration, max_steps steps), first sample at t = 0: the
// signal is generated once at 0.05 ms for 20 s and interpolated linearly (first-order hold) at
// t = n dt, n an integer (the same samples as the trade-off bench where dt is a multiple).
std::vector<double> lorry_input(double dt_s, double duration_s, std::uint64_t max_steps);

// Runs one cell (params complete: model, law, c, integrator, dt, friction, damping).
Cell run_cell(const OscillatorParams& params, bool in_float, double den_hartog_k,
              double damping_ratio, const std::vector<double>& lorry,
              std::uint64_t free_decay_steps);

// Every cell of the grid, in a fixed order; `progress` (may be null) is called after each dt.
std::vector<Cell> run_map(const MapGrid& grid, void (*progress)(double dt_s, std::size_t done));

// docs/STABILITY.md: the criteria, per model x integrator a summary, the refusal reasons, every
// unstable cell, and the command that made it.
std::string markdown_report(const MapGrid& grid, const std::vector<Cell>& cells,
                            const std::string& command, double seconds);

}  // namespace stickslip::reliability
