// Validation of `stickslip fit` (run/fit.hpp) on synthetic rig data it did not make: a lorry-like
// floor signal (`stickslip generate --kind lorry`), the seat's a_x from the event-driven reference
// solver (run/reference_solver.hpp, independent of the core's step maps and event search that
// the fit simulates with), white accelerometer noise on a_x and a_u (seeded). Per trial the
// relative errors of k, b, F_fk, F_fs and whether each 95 % interval covers the truth; at the end
// the coverage per parameter. Exit status 1 when an error exceeds its tolerance (k, b: 2 %; F_fk,
// F_fs: 3 %) or a coverage is below --min-coverage.
//
//   stickslip_fit_validation [--trials N] [--first-seed S] [--K K1,K2,...] [--duration S]
//                            [--min-coverage C]
//   stickslip_fit_validation --write-rig FILE [--seed S] [--K K] [--duration S]
//                            [--shift-samples N] [--ax-in-g] [--unit-header] [--no-ax] [--travel]
//                            [--static-ratio R]
// (--write-rig: one rig recording t,a_u,a_x[,x_r] for the command-line tests; --ax-in-g divides
// a_x by g, --unit-header names the units in the header, --shift-samples delays a_x.)
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/fit.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/random.hpp"
#include "stickslip/host/signals/signal_generator.hpp"

using namespace stickslip;
using namespace stickslip::host;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kStandardGravity_m_per_s2 = 9.80665;

struct RigSpec {
  std::uint64_t seed = 1;
  double den_hartog_k = 0.8;
  double static_ratio = 1.2;  // F_fs / F_fk of the truth
  double rms_m_per_s2 = 0.6;
  double duration_s = 120.0;
  double dt_s = 1e-3;
  double noise_m_per_s2 = 0.02;       // the seat accelerometer
  double floor_noise_m_per_s2 = 0.0;  // the floor accelerometer (--floor-noise)
  double travel_noise_m = 3e-5;
  bool travel = false;
};

// The seat of the validation: m = 88.4 kg, k = 11500 N/m, b = 504 N s/m, F_fk from Den Hartog's
// K = 4 F_fk / (pi sqrt(2) m rms_u).
OscillatorParams truth_for(const RigSpec& spec) {
  OscillatorParams truth;
  truth.model = FrictionModel::stick_slip;
  truth.dt_s = spec.dt_s;
  truth.kinetic_friction_n =
      spec.den_hartog_k * kPi * std::sqrt(2.0) * truth.mass_kg * spec.rms_m_per_s2 / 4.0;
  truth.static_friction_n = spec.static_ratio * truth.kinetic_friction_n;
  return truth;
}

RigRecording make_rig(const RigSpec& spec, const OscillatorParams& truth) {
  GeneratorSpec floor;
  floor.kind = SignalKind::lorry;
  floor.rms_m_per_s2 = spec.rms_m_per_s2;
  floor.duration_s = spec.duration_s;
  floor.dt_s = spec.dt_s;
  floor.seed = spec.seed;
  const std::vector<double> a_u = generate_signal(floor);
  const ReferenceTrace seat = solve_reference(truth, a_u);
  GaussianSource seat_noise(spec.seed, 101), floor_noise(spec.seed, 102),
      travel_noise(spec.seed, 103);
  RigRecording rig;
  rig.path = "synthetic";
  rig.dt_s = spec.dt_s;
  for (std::size_t n = 0; n < a_u.size(); ++n) {
    rig.t_s.push_back(static_cast<double>(n) * spec.dt_s);
    rig.a_u_m_per_s2.push_back(a_u[n] + spec.floor_noise_m_per_s2 * floor_noise.next());
    rig.a_x_m_per_s2.push_back(seat.a_x_m_per_s2[n] + spec.noise_m_per_s2 * seat_noise.next());
    if (spec.travel) rig.x_r_m.push_back(seat.x_r_m[n] + spec.travel_noise_m * travel_noise.next());
  }
  return rig;
}

struct WriteOptions {
  long shift_samples = 0;
  bool ax_in_g = false, unit_header = false, no_ax = false;
};

int write_rig(const char* path, const RigRecording& rig, const WriteOptions& options) {
  std::FILE* file = std::fopen(path, "w");
  if (file == nullptr) return 1;
  const char* ax_unit = options.ax_in_g ? " [g]" : " [m/s^2]";
  if (options.unit_header) {
    std::fprintf(file, "t [s],a_u [m/s^2]%s%s%s\n", options.no_ax ? "" : ",a_x",
                 options.no_ax ? "" : ax_unit, rig.has_travel() ? ",x_r [m]" : "");
  } else {
    std::fprintf(file, "t,a_u%s%s\n", options.no_ax ? "" : ",a_x", rig.has_travel() ? ",x_r" : "");
  }
  const long count = static_cast<long>(rig.t_s.size());
  for (long n = 0; n < count; ++n) {
    const long source = std::min(std::max(n - options.shift_samples, 0L), count - 1);
    double a_x = rig.a_x_m_per_s2[static_cast<std::size_t>(source)];
    if (options.ax_in_g) a_x /= kStandardGravity_m_per_s2;
    std::fprintf(file, "%.17g,%.17g", rig.t_s[static_cast<std::size_t>(n)],
                 rig.a_u_m_per_s2[static_cast<std::size_t>(n)]);
    if (!options.no_ax) std::fprintf(file, ",%.17g", a_x);
    if (rig.has_travel()) std::fprintf(file, ",%.17g", rig.x_r_m[static_cast<std::size_t>(n)]);
    std::fprintf(file, "\n");
  }
  return std::fclose(file) == 0 ? 0 : 1;
}

struct Tally {
  int trials = 0, failures = 0;
  int covered[4] = {0, 0, 0, 0};
  int covered_hac[4] = {0, 0, 0, 0};
  double width_sum[4] = {0, 0, 0, 0}, width_hac_sum[4] = {0, 0, 0, 0};  // relative half-widths
  double worst[4] = {0, 0, 0, 0};
  double slowest_s = 0.0;
};

constexpr FitParameter kChecked[4] = {FitParameter::stiffness, FitParameter::damping,
                                      FitParameter::ffk, FitParameter::ffs};
constexpr double kTolerance[4] = {0.02, 0.02, 0.03, 0.03};

void run_trial(const RigSpec& spec, Tally& tally) {
  const OscillatorParams truth = truth_for(spec);
  const RigRecording rig = make_rig(spec, truth);
  FitRequest request;
  request.mass_kg = truth.mass_kg;
  for (FitParameter parameter : kChecked) request.fit[static_cast<std::size_t>(parameter)] = true;
  const std::clock_t cpu_start = std::clock();
  const FitResult result = fit_seat(rig, request);
  const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double true_value[4] = {truth.stiffness_n_per_m, truth.damping_ns_per_m,
                                truth.kinetic_friction_n, truth.static_friction_n};
  std::string row = fmt::format("| {:.2f} | {} |", spec.den_hartog_k, spec.seed);
  bool ok = result.converged;
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(kChecked[i]);
    const double error = result.value[k] / true_value[i] - 1.0;
    const bool covered = std::fabs(result.value[k] - true_value[i]) <= result.ci95[k];
    tally.covered[i] += covered ? 1 : 0;
    const bool covered_hac = std::fabs(result.value[k] - true_value[i]) <= result.ci95_hac[k];
    tally.covered_hac[i] += covered_hac ? 1 : 0;
    tally.width_sum[i] += result.ci95[k] / true_value[i];
    tally.width_hac_sum[i] += result.ci95_hac[k] / true_value[i];
    tally.worst[i] = std::max(tally.worst[i], std::fabs(error));
    ok = ok && std::fabs(error) <= kTolerance[i];
    row += fmt::format(" {:+.3f} % ({:.3f} %{}) |", 100.0 * error,
                       100.0 * result.ci95[k] / true_value[i], covered ? "" : ", missed");
  }
  row += " HAC:";
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(kChecked[i]);
    row += fmt::format(
        " {:.3f} %{}", 100.0 * result.ci95_hac[k] / true_value[i],
        std::fabs(result.value[k] - true_value[i]) <= result.ci95_hac[k] ? "" : " missed");
  }
  row += fmt::format(" (L {}, rho1 {:.3f}) |", result.hac_lag, result.residual_lag1_correlation);
  row += fmt::format(" {:.4f} | {:.4f} / {:.4f} | {} | {:.2f} / {:.2f} |{}",
                     result.rms_residual_m_per_s2, result.stick_probability_measured,
                     result.stick_probability_model, result.iterations, result.seconds, cpu_s,
                     ok ? "" : " FAIL");
  std::puts(row.c_str());
  std::fflush(stdout);
  ++tally.trials;
  tally.failures += ok ? 0 : 1;
  tally.slowest_s = std::max(tally.slowest_s, cpu_s);
}

std::vector<double> parse_list(const char* text) {
  std::vector<double> values;
  for (const char* p = text; *p != '\0';) {
    char* end = nullptr;
    values.push_back(std::strtod(p, &end));
    p = *end == ',' ? end + 1 : end;
    if (end == p && *end != '\0') break;
  }
  return values;
}

int run_trials(const RigSpec& base, const std::vector<double>& ks, int trials,
               std::uint64_t first_seed, double min_coverage) {
  std::puts(
      "| K | seed | k err (CI) | b err (CI) | F_fk err (CI) | F_fs err (CI) | HAC intervals | "
      "rms res | p meas / model | iter | wall / CPU s |");
  std::puts("|---|---|---|---|---|---|---|---|---|---|---|");
  Tally tally;
  for (int t = 0; t < trials; ++t) {
    RigSpec spec = base;
    spec.seed = first_seed + static_cast<std::uint64_t>(t);
    spec.den_hartog_k = ks[static_cast<std::size_t>(t) % ks.size()];
    run_trial(spec, tally);
  }
  const char* names[4] = {"k", "b", "F_fk", "F_fs"};
  bool coverage_ok = true;
  std::string summary = fmt::format("{} trials, {} outside the tolerances (2/2/3/3 %);",
                                    tally.trials, tally.failures);
  for (int i = 0; i < 4; ++i) {
    const double coverage = static_cast<double>(tally.covered[i]) / tally.trials;
    coverage_ok = coverage_ok && coverage >= min_coverage;
    summary += fmt::format(" {}: worst {:.3f} %, coverage {}/{}", names[i], 100.0 * tally.worst[i],
                           tally.covered[i], tally.trials);
  }
  summary += fmt::format("; slowest fit {:.2f} s of CPU", tally.slowest_s);
  summary += "; mean 95 % half-width classic / HAC:";
  for (int i = 0; i < 4; ++i) {
    summary += fmt::format(" {} {:.3f} / {:.3f} % (HAC coverage {}/{})", names[i],
                           100.0 * tally.width_sum[i] / tally.trials,
                           100.0 * tally.width_hac_sum[i] / tally.trials, tally.covered_hac[i],
                           tally.trials);
  }
  std::puts(summary.c_str());
  return tally.failures == 0 && coverage_ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  RigSpec spec;
  WriteOptions write;
  const char* rig_path = nullptr;
  std::vector<double> ks = {0.3, 0.6, 1.0, 1.5};
  int trials = 8;
  std::uint64_t first_seed = 1;
  double min_coverage = 0.9;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--trials") && has_value) {
      trials = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--first-seed") && has_value) {
      first_seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--seed") && has_value) {
      spec.seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--K") && has_value) {
      ks = parse_list(argv[++i]);
      spec.den_hartog_k = ks.front();
    } else if (!std::strcmp(argv[i], "--duration") && has_value) {
      spec.duration_s = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--static-ratio") && has_value) {
      spec.static_ratio = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--floor-noise") && has_value) {
      spec.floor_noise_m_per_s2 = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--min-coverage") && has_value) {
      min_coverage = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--write-rig") && has_value) {
      rig_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--shift-samples") && has_value) {
      write.shift_samples = std::atol(argv[++i]);
    } else if (!std::strcmp(argv[i], "--ax-in-g")) {
      write.ax_in_g = true;
    } else if (!std::strcmp(argv[i], "--unit-header")) {
      write.unit_header = true;
    } else if (!std::strcmp(argv[i], "--no-ax")) {
      write.no_ax = true;
    } else if (!std::strcmp(argv[i], "--travel")) {
      spec.travel = true;
    } else {
      std::fprintf(stderr, "stickslip_fit_validation: unknown or incomplete option '%s'\n",
                   argv[i]);
      return 2;
    }
  }
  if (ks.empty() || trials < 1) {
    std::fputs("stickslip_fit_validation: --K needs values and --trials >= 1\n", stderr);
    return 2;
  }
  try {
    if (rig_path != nullptr) return write_rig(rig_path, make_rig(spec, truth_for(spec)), write);
    return run_trials(spec, ks, trials, first_seed, min_coverage);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "stickslip_fit_validation: %s\n", error.what());
    return 1;
  }
}
