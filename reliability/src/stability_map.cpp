#include "stickslip/reliability/stability_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/dispatch.hpp"

namespace stickslip::reliability {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBaseDtS = 5e-5;
constexpr double kBaseDurationS = 20.0;

std::string format(const char* pattern, double value) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

const std::vector<double>& base_lorry() {
  static const std::vector<double> base = [] {
    host::GeneratorSpec spec;
    spec.kind = host::SignalKind::lorry;
    spec.rms_m_per_s2 = kLorryRms;
    spec.duration_s = kBaseDurationS;
    spec.dt_s = kBaseDtS;
    spec.seed = 1;
    return host::generate_signal(spec);
  }();
  return base;
}

struct SceneCheck {
  bool finite = true;
  bool bounded = true;
  double energy_first = 0.0, energy_last = 0.0, energy_max = 0.0;
  std::uint64_t budget = 0, resets = 0;
};

template <typename T>
bool finite_output(const StepOutput<T>& out) {
  return std::isfinite(out.x_r_m) && std::isfinite(out.v_r_m_per_s) &&
         std::isfinite(out.a_x_m_per_s2) && std::isfinite(out.friction_n) &&
         std::isfinite(out.stuck_time_s);
}

template <typename T, typename Seat>
SceneCheck free_decay(Seat& seat, const OscillatorParams& p, std::uint64_t steps) {
  SceneCheck c;
  seat.reset(static_cast<T>(kFreeDecayX0M), T(0), T(0));
  auto energy = [&](double x, double v) {
    return 0.5 * p.stiffness_n_per_m * x * x + 0.5 * p.mass_kg * v * v;
  };
  const double e0 = energy(static_cast<double>(seat.x_r()), 0.0);
  c.energy_max = e0;
  for (std::uint64_t n = 1; n <= steps; ++n) {
    const auto out = seat.step(T(0));
    if (!finite_output(out)) c.finite = false;
    const double e = energy(static_cast<double>(out.x_r_m), static_cast<double>(out.v_r_m_per_s));
    if (!(e <= c.energy_max)) c.energy_max = e;  // NaN shows as a maximum too
    if (3 * n <= steps && !(e <= c.energy_first)) c.energy_first = e;
    if (3 * n > 2 * steps && !(e <= c.energy_last)) c.energy_last = e;
  }
  // Held laws with explicit integrators chatter once the seat should stick (README: period 2 dt):
  // a bounded limit cycle whose velocity swings by up to F_fk dt/m per step. Its energy, up to
  // 2 F_fk^2 dt^2/m, is allowed on top of the ceiling; growth (below) still counts.
  const bool chatters = (p.model == FrictionModel::signum || p.model == FrictionModel::smooth) &&
                        p.integrator != Integrator::exact;
  const double chatter =
      chatters ? 2.0 * p.kinetic_friction_n * p.kinetic_friction_n * p.dt_s * p.dt_s / p.mass_kg
               : 0.0;
  c.energy_max = c.energy_max / (e0 + chatter / kEnergyCeiling);
  c.budget = seat.event_budget_exhausted();
  c.resets = seat.state_resets();
  return c;
}

template <typename T, typename Seat>
SceneCheck lorry_run(Seat& seat, const std::vector<double>& input) {
  SceneCheck c;
  seat.reset(T(0), T(0), static_cast<T>(input[0]));
  for (std::size_t n = 1; n < input.size(); ++n) {
    const auto out = seat.step(static_cast<T>(input[n]));
    if (!finite_output(out)) c.finite = false;
    if (!(std::fabs(static_cast<double>(out.x_r_m)) <= kTravelBoundM)) c.bounded = false;
  }
  c.budget = seat.event_budget_exhausted();
  c.resets = seat.state_resets();
  return c;
}

// The first criterion that fires, or "" for a stable cell.
std::string judge(const SceneCheck& decay, const SceneCheck& lorry) {
  std::string why;
  auto add = [&](const std::string& text) {
    if (!why.empty()) why += "; ";
    why += text;
  };
  if (!decay.finite || !lorry.finite) add("NaN/Inf output");
  if (decay.resets + lorry.resets > 0)
    add(format("%g state resets", static_cast<double>(decay.resets + lorry.resets)));
  if (decay.budget + lorry.budget > 0)
    add(format("event budget exhausted in %g steps",
               static_cast<double>(decay.budget + lorry.budget)));
  if (!(decay.energy_max <= kEnergyCeiling))
    add(format("free decay energy reached %.3g x its ceiling", decay.energy_max / kEnergyCeiling));
  else if (decay.energy_first > 0.0 &&
           !(decay.energy_last <= kEnergyGrowthBound * decay.energy_first))
    add(format("free decay energy grew %.3g x from the first to the last third",
               decay.energy_last / decay.energy_first));
  if (!lorry.bounded) add("|x_r| > 1 m on the lorry input");
  return why;
}

template <typename T>
Cell run_typed(const OscillatorParams& params, const std::vector<double>& lorry,
               std::uint64_t free_decay_steps) {
  return with_oscillator<T>(params, [&](auto& seat) {
    Cell cell;
    cell.params = params;
    const auto config = seat.configure(params);
    if (!config.ok()) {
      cell.verdict = Verdict::refused;
      cell.reason = config.message.c_str();
      return cell;
    }
    const SceneCheck decay = free_decay<T>(seat, params, free_decay_steps);
    const SceneCheck run = lorry_run<T>(seat, lorry);
    cell.reason = judge(decay, run);
    cell.verdict = cell.reason.empty() ? Verdict::stable : Verdict::unstable;
    return cell;
  });
}

// The parameter a refusal names: the message starts with "<parameter>:".
std::string refusal_parameter(const std::string& message) {
  const auto colon = message.find(':');
  return colon == std::string::npos ? message : message.substr(0, colon);
}

}  // namespace

const char* verdict_name(Verdict verdict) noexcept {
  switch (verdict) {
    case Verdict::refused:
      return "refused";
    case Verdict::stable:
      return "stable";
    case Verdict::unstable:
      return "unstable";
  }
  return "?";
}

MapGrid full_grid() {
  MapGrid g;
  g.den_hartog_k = {0.0, 0.1, 0.4, 0.8, 1.5, 3.0, 10.0, 100.0};
  g.damping_ratio = {0.0, 0.05, 0.25, 1.0, 2.0};
  g.smoothing_c = {1.0, 1e3, 1e6};
  g.dt_s = {1e-5, 1e-4, 2.5e-4, 1e-3, 5e-3, 1e-2, 0.05};
  return g;
}

MapGrid coarse_grid() {
  MapGrid g;
  g.den_hartog_k = {0.0, 0.8, 10.0, 100.0};
  g.damping_ratio = {0.0, 0.25, 2.0};
  g.smoothing_c = {1.0, 1e6};
  g.dt_s = {1e-5, 2.5e-4, 5e-3, 0.05};
  g.lorry_duration_s = 4.0;
  g.free_decay_duration_s = 2.0;
  g.max_steps = 4000;
  return g;
}

std::string law_label(const OscillatorParams& params) {
  std::string label = model_name(params.model);
  if (params.model == FrictionModel::smooth)
    label += std::string("/") + smoothing_name(params.smoothing);
  return label;
}

std::string describe(const Cell& cell) {
  const OscillatorParams& p = cell.params;
  char buffer[320];
  std::snprintf(
      buffer, sizeof buffer, "%s %s %s K=%g zeta=%g%s dt=%g s", cell.in_float ? "float" : "double",
      law_label(p).c_str(), integrator_name(p.integrator), cell.den_hartog_k, cell.damping_ratio,
      p.model == FrictionModel::smooth ? format(" c=%g s/m", p.smoothing_constant_s_per_m).c_str()
                                       : "",
      p.dt_s);
  return buffer;
}

std::vector<double> lorry_input(double dt_s, double duration_s, std::uint64_t max_steps) {
  const std::vector<double>& base = base_lorry();
  const double wanted = std::floor(std::min(duration_s, kBaseDurationS) / dt_s + 1e-9);
  const std::uint64_t steps =
      std::min<std::uint64_t>(max_steps, static_cast<std::uint64_t>(wanted));
  std::vector<double> out(steps + 1);
  for (std::uint64_t n = 0; n <= steps; ++n) {
    const double position = static_cast<double>(n) * (dt_s / kBaseDtS);
    const double whole = std::round(position);
    if (std::fabs(position - whole) <= 1e-9 * (whole + 1.0)) {  // on a base sample: take it
      out[n] = base[static_cast<std::size_t>(whole)];
      continue;
    }
    const auto i = static_cast<std::size_t>(std::floor(position));
    const double frac = position - static_cast<double>(i);
    out[n] = (1.0 - frac) * base[i] + frac * base[i + 1];
  }
  return out;
}

Cell run_cell(const OscillatorParams& params, bool in_float, double den_hartog_k,
              double damping_ratio, const std::vector<double>& lorry,
              std::uint64_t free_decay_steps) {
  Cell cell = in_float ? run_typed<float>(params, lorry, free_decay_steps)
                       : run_typed<double>(params, lorry, free_decay_steps);
  cell.in_float = in_float;
  cell.den_hartog_k = den_hartog_k;
  cell.damping_ratio = damping_ratio;
  return cell;
}

std::vector<Cell> run_map(const MapGrid& grid, void (*progress)(double, std::size_t)) {
  struct Law {
    FrictionModel model;
    SmoothingLaw smoothing;
    double c;
  };
  std::vector<Law> laws = {{FrictionModel::linear, SmoothingLaw::tanh, 1e3},
                           {FrictionModel::signum, SmoothingLaw::tanh, 1e3},
                           {FrictionModel::stick_slip, SmoothingLaw::tanh, 1e3},
                           {FrictionModel::stribeck, SmoothingLaw::tanh, 1e3}};
  for (SmoothingLaw s :
       {SmoothingLaw::atan, SmoothingLaw::tanh, SmoothingLaw::erf, SmoothingLaw::rational})
    for (double c : grid.smoothing_c) laws.push_back({FrictionModel::smooth, s, c});
  const Integrator integrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                    Integrator::exact};
  std::vector<bool> types;
  if (grid.in_double) types.push_back(false);
  if (grid.in_float) types.push_back(true);

  std::vector<Cell> cells;
  for (double dt : grid.dt_s) {
    const std::vector<double> lorry = lorry_input(dt, grid.lorry_duration_s, grid.max_steps);
    const std::uint64_t decay_steps = std::min<std::uint64_t>(
        grid.max_steps, static_cast<std::uint64_t>(std::ceil(grid.free_decay_duration_s / dt)));
    for (const Law& law : laws)
      for (Integrator integrator : integrators)
        for (double k_factor : grid.den_hartog_k)
          for (double zeta : grid.damping_ratio)
            for (bool in_float : types) {
              OscillatorParams p;  // the reference seat
              p.model = law.model;
              p.smoothing = law.smoothing;
              p.smoothing_constant_s_per_m = law.c;
              p.integrator = integrator;
              p.dt_s = dt;
              p.damping_ns_per_m = zeta * 2.0 * std::sqrt(p.stiffness_n_per_m * p.mass_kg);
              p.kinetic_friction_n = k_factor * kPi * std::sqrt(2.0) * p.mass_kg * kLorryRms / 4.0;
              p.static_friction_n = law.model == FrictionModel::stribeck
                                        ? kStribeckRatio * p.kinetic_friction_n
                                        : p.kinetic_friction_n;
              p.stribeck_velocity_m_per_s = 0.01;
              cells.push_back(run_cell(p, in_float, k_factor, zeta, lorry, decay_steps));
            }
    if (progress != nullptr) progress(dt, cells.size());
  }
  return cells;
}

namespace {

// What the map covers and what makes a cell unstable.
std::string grid_section(const MapGrid& grid, std::size_t cell_count, const std::string& command,
                         double seconds) {
  auto list = [](const std::vector<double>& values) {
    std::string out;
    for (double v : values) out += (out.empty() ? "" : ", ") + format("%g", v);
    return out;
  };
  std::string md;
  md += "# Stability map\n\n";
  md += "Generated by `" + command + "` (" + format("%.0f", seconds) + " s, " +
        format("%.0f", static_cast<double>(cell_count)) + " cells). Do not edit by hand.\n\n";
  md +=
      "Every friction law x integrator x scalar type on the reference seat (m = 88.4 kg, "
      "k = 11.5 kN/m) over\n\n";
  md += "- Den Hartog's K: " + list(grid.den_hartog_k) +
        " (F_fk = K pi sqrt(2) m a0u / 4, a0u = 0.35 m/s^2; Stribeck F_fs = 1.3 F_fk, v_S = "
        "0.01 m/s; stick-slip F_fs = F_fk)\n";
  md += "- damping ratio: " + list(grid.damping_ratio) + "\n";
  md += "- smoothing constant c (smooth laws): " + list(grid.smoothing_c) + " s/m\n";
  md += "- dt: " + list(grid.dt_s) + " s\n\n";
  md += "Each accepted cell runs a free decay (x_r(0) = 5 cm, a_u = 0, " +
        format("%g", grid.free_decay_duration_s) + " s) and the lorry-like input (" +
        format("%g", grid.lorry_duration_s) + " s), each capped at " +
        format("%.0f", static_cast<double>(grid.max_steps)) +
        " steps. It is **unstable** if any output is NaN/Inf, any step exhausts the event budget, "
        "the non-finite guard restarts the state, the free decay's energy exceeds 2 E(0) (plus, "
        "for signum and smooth laws with the explicit integrators, the energy of their documented "
        "chatter, a bounded limit cycle swinging the velocity by up to F_fk dt/m per step: "
        "2 F_fk^2 dt^2/m) or its "
        "maximum over the last third exceeds 1.1 x its maximum over the first third (a passive "
        "seat's energy cannot grow with a_u = 0; the band allows the explicit schemes' bounded "
        "energy oscillation), or |x_r| exceeds 1 m on the lorry input (a passive seat answers "
        "it with centimetres). **Refused** cells are refused by `configure()`; the reason is the "
        "parameter its message names.\n\n";
  return md;
}

// Summary per law x integrator; counts the unstable cells.
std::string summary_section(const std::vector<Cell>& cells, int& total_unstable) {
  std::string md;
  struct Tally {
    int cells = 0, stable = 0, unstable = 0;
    std::map<std::string, int> refused;
  };
  std::map<std::string, Tally> tallies;
  std::vector<std::string> order;
  for (const Cell& c : cells) {
    const std::string key = law_label(c.params) + " | " + integrator_name(c.params.integrator) +
                            " | " + (c.in_float ? "float" : "double");
    if (tallies.find(key) == tallies.end()) order.push_back(key);
    Tally& t = tallies[key];
    ++t.cells;
    if (c.verdict == Verdict::stable) ++t.stable;
    if (c.verdict == Verdict::unstable) ++t.unstable;
    if (c.verdict == Verdict::refused) ++t.refused[refusal_parameter(c.reason)];
  }
  int total_refused = 0, total_stable = 0;
  md +=
      "## Summary\n\n| law | integrator | type | cells | stable | unstable | refused (by the "
      "parameter named) |\n|---|---|---|---:|---:|---:|---|\n";
  std::sort(order.begin(), order.end());
  for (const std::string& key : order) {
    const Tally& t = tallies[key];
    std::string refused;
    int refused_count = 0;
    for (const auto& [name, count] : t.refused) {
      refused += (refused.empty() ? "" : ", ") + name + " " + format("%g", count);
      refused_count += count;
    }
    if (refused.empty()) refused = "0";
    total_unstable += t.unstable;
    total_refused += refused_count;
    total_stable += t.stable;
    md += "| " + key + " | " + format("%g", t.cells) + " | " + format("%g", t.stable) + " | " +
          format("%g", t.unstable) + " | " + refused + " |\n";
  }
  md += "\nTotal: " + format("%g", total_stable) + " stable, " + format("%g", total_unstable) +
        " unstable, " + format("%g", total_refused) + " refused.\n\n";
  return md;
}

// The unstable accepted cells, and one example message per distinct refusal kind (parameter +
// message up to the first digit).
std::string cells_section(const std::vector<Cell>& cells, int total_unstable) {
  std::string md;
  md += "## Unstable accepted cells\n\n";
  if (total_unstable == 0) md += "None.\n";
  for (const Cell& c : cells)
    if (c.verdict == Verdict::unstable) md += "- " + describe(c) + ": " + c.reason + "\n";

  md += "\n## Refusal messages (one example per kind)\n\n";
  std::map<std::string, std::string> examples;
  for (const Cell& c : cells) {
    if (c.verdict != Verdict::refused) continue;
    std::string kind = c.reason.substr(0, c.reason.find_first_of("0123456789"));
    if (examples.find(kind) == examples.end())
      examples[kind] = describe(c) + ": `" + c.reason + "`";
  }
  for (const auto& [kind, example] : examples) md += "- " + example + "\n";
  return md;
}

}  // namespace

std::string markdown_report(const MapGrid& grid, const std::vector<Cell>& cells,
                            const std::string& command, double seconds) {
  int total_unstable = 0;
  std::string md = grid_section(grid, cells.size(), command, seconds);
  md += summary_section(cells, total_unstable);
  md += cells_section(cells, total_unstable);
  return md;
}

}  // namespace stickslip::reliability
