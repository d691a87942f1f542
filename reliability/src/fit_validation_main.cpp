// Validation of `stickslip fit` (run/fit.hpp) on synthetic rig data it did not make: a lorry-like
// floor signal (`stickslip generate --kind lorry`), the seat's a_x from the event-driven reference
// solver (run/reference_solver.hpp, independent of the core's step maps and event search that
// the fit simulates with), white accelerometer noise on a_x and a_u (seeded). Per trial the
// relative errors of k, b, F_fk, F_fs and whether each 95 % interval covers the truth; at the end
// the coverage per parameter. Per trial also the truth's own residual RMS (a fit above it stopped
// short of the minimum) and the Cramer-Rao standard deviations (the Gauss-Newton ones with the
// Jacobian at the truth and the known noise, fit.hpp probe_fit). Exit status 1 when an error
// exceeds its tolerance (k, b: 2 %; F_fk, F_fs: 3 %) or a coverage is below --min-coverage.
//
//   stickslip_fit_validation [--trials N] [--first-seed S | --seeds S1,S2,...] [--K K1,K2,...]
//                            [--duration S] [--min-coverage C] [--travel] [--floor-noise A]
//                            [--jobs J]
//   stickslip_fit_validation --write-rig FILE [--seed S] [--K K] [--duration S]
//                            [--shift-samples N] [--ax-in-g] [--unit-header] [--no-ax] [--travel]
//                            [--static-ratio R]
// (--write-rig: one rig recording t,a_u,a_x[,x_r] for the command-line tests; --ax-in-g divides
// a_x by g, --unit-header names the units in the header, --shift-samples delays a_x.)
#include <fmt/format.h>

#include <time.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
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
  int within[4] = {0, 0, 0, 0};  // |error| within the tolerance
  int covered[4] = {0, 0, 0, 0};
  int covered_hac[4] = {0, 0, 0, 0};
  double width_sum[4] = {0, 0, 0, 0}, width_hac_sum[4] = {0, 0, 0, 0};  // relative half-widths
  double worst[4] = {0, 0, 0, 0};
  int above_truth = 0;  // fits whose residual is above the truth's (the optimiser stopped short)
  double largest_crb_ffs = 0.0;  // relative Cramer-Rao standard deviation of F_fs
  std::vector<double> cpu_s;
};

constexpr FitParameter kChecked[4] = {FitParameter::stiffness, FitParameter::damping,
                                      FitParameter::ffk, FitParameter::ffs};
constexpr double kTolerance[4] = {0.02, 0.02, 0.03, 0.03};

// One fit's figures against the truth.
struct Outcome {
  bool within[4] = {}, covered[4] = {}, covered_hac[4] = {};
  double width[4] = {}, width_hac[4] = {}, error[4] = {};
  double crb_ffs = 0.0;
  bool above_truth = false, ok = false;
  double cpu_s = 0.0;
};

void add_trial(Tally& tally, const Outcome& o) {
  ++tally.trials;
  tally.failures += o.ok ? 0 : 1;
  for (int i = 0; i < 4; ++i) {
    tally.within[i] += o.within[i] ? 1 : 0;
    tally.covered[i] += o.covered[i] ? 1 : 0;
    tally.covered_hac[i] += o.covered_hac[i] ? 1 : 0;
    tally.width_sum[i] += o.width[i];
    tally.width_hac_sum[i] += o.width_hac[i];
    tally.worst[i] = std::max(tally.worst[i], std::fabs(o.error[i]));
  }
  tally.above_truth += o.above_truth ? 1 : 0;
  tally.largest_crb_ffs = std::max(tally.largest_crb_ffs, o.crb_ffs);
  tally.cpu_s.push_back(o.cpu_s);
}

// CPU time of the calling thread (the fits run on --jobs threads).
double thread_cpu_s() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// One fit; prints its row (under `print`) and returns its figures.
Outcome run_trial(const RigSpec& spec, std::mutex& print) {
  const OscillatorParams truth = truth_for(spec);
  const RigRecording rig = make_rig(spec, truth);
  FitRequest request;
  request.mass_kg = truth.mass_kg;
  if (spec.travel) request.travel_noise_m = spec.travel_noise_m;
  for (FitParameter parameter : kChecked) request.fit[static_cast<std::size_t>(parameter)] = true;
  const double cpu_start = thread_cpu_s();
  const FitResult result = fit_seat(rig, request);
  const double cpu_s = thread_cpu_s() - cpu_start;
  // The truth's own residual, and the Gauss-Newton intervals with the Jacobian at the truth and
  // the known noise: the Cramer-Rao bound (fit.hpp, probe_fit).
  const FitProbe at_truth = probe_fit(rig, request, truth);
  const double true_value[4] = {truth.stiffness_n_per_m, truth.damping_ns_per_m,
                                truth.kinetic_friction_n, truth.static_friction_n};
  std::string row = fmt::format("| {:.2f} | {} |", spec.den_hartog_k, spec.seed);
  Outcome o;
  bool ok = result.converged;
  double crb[4];
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(kChecked[i]);
    o.error[i] = result.value[k] / true_value[i] - 1.0;
    o.within[i] = std::fabs(o.error[i]) <= kTolerance[i];
    o.covered[i] = std::fabs(result.value[k] - true_value[i]) <= result.ci95[k];
    o.covered_hac[i] = std::fabs(result.value[k] - true_value[i]) <= result.ci95_hac[k];
    o.width[i] = result.ci95[k] / true_value[i];
    o.width_hac[i] = result.ci95_hac[k] / true_value[i];
    crb[i] = at_truth.ci95[k] / 1.959963984540054 * spec.noise_m_per_s2 /
             at_truth.rms_residual_m_per_s2 / true_value[i];
    ok = ok && o.within[i];
    row += fmt::format(" {:+.3f} % ({:.3f} %{}) |", 100.0 * o.error[i], 100.0 * o.width[i],
                       o.covered[i] ? "" : ", missed");
  }
  row += " HAC:";
  for (int i = 0; i < 4; ++i)
    row += fmt::format(" {:.3f} %{}", 100.0 * o.width_hac[i], o.covered_hac[i] ? "" : " missed");
  row += fmt::format(" (L {}, rho1 {:.3f}) |", result.hac_lag, result.residual_lag1_correlation);
  row += " CRB sd:";
  for (int i = 0; i < 4; ++i) row += fmt::format(" {:.3f} %", 100.0 * crb[i]);
  // 1e-9 relative: the two costs are sums of 120000 squares, equal to rounding when both are the
  // same minimum.
  const bool above_truth =
      result.rms_residual_m_per_s2 > at_truth.rms_residual_m_per_s2 * (1.0 + 1e-9);
  row += fmt::format(" | {:.5f} / {:.5f}{} | {:.4f} / {:.4f} | {} | {} + {} | {:.2f} / {:.2f} |{}",
                     result.rms_residual_m_per_s2, at_truth.rms_residual_m_per_s2,
                     above_truth ? " above" : "", result.stick_probability_measured,
                     result.stick_probability_model, result.iterations, result.local_runs,
                     result.search_evaluations, result.seconds, cpu_s, ok ? "" : " FAIL");
  {
    const std::lock_guard<std::mutex> lock(print);
    std::puts(row.c_str());
    std::fflush(stdout);
  }
  o.crb_ffs = crb[3];
  o.above_truth = above_truth;
  o.ok = ok;
  o.cpu_s = cpu_s;
  return o;
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

std::string percent(int count, int trials) {
  return fmt::format("{:.0f}", 100.0 * count / trials);
}

// One row of the summary table (docs/IDENTIFICATION.md, "Validation").
std::string summary_row(const std::string& label, const Tally& t) {
  const std::vector<double>& cpu = t.cpu_s;
  return fmt::format(
      "| {} | {} | {} / {} / {} / {} | {:.3f} / {:.3f} / {:.3f} / {:.3f} % | {} / {} / {} / {} "
      "({} / {} / {} / {} %) | {:.3f} / {:.3f} / {:.3f} / {:.3f} % | {} | {:.2f} % | {:.2f} / "
      "{:.2f} |",
      label, t.trials, t.within[0], t.within[1], t.within[2], t.within[3], 100.0 * t.worst[0],
      100.0 * t.worst[1], 100.0 * t.worst[2], 100.0 * t.worst[3], t.covered[0], t.covered[1],
      t.covered[2], t.covered[3], percent(t.covered[0], t.trials), percent(t.covered[1], t.trials),
      percent(t.covered[2], t.trials), percent(t.covered[3], t.trials),
      100.0 * t.width_sum[0] / t.trials, 100.0 * t.width_sum[1] / t.trials,
      100.0 * t.width_sum[2] / t.trials, 100.0 * t.width_sum[3] / t.trials, t.above_truth,
      100.0 * t.largest_crb_ffs, median(cpu), *std::max_element(cpu.begin(), cpu.end()));
}

int run_trials(const RigSpec& base, const std::vector<double>& ks,
               const std::vector<std::uint64_t>& seeds, double min_coverage, int jobs) {
  const int trials = static_cast<int>(seeds.size());
  std::puts(
      "| K | seed | k err (CI) | b err (CI) | F_fk err (CI) | F_fs err (CI) | HAC intervals | "
      "rms res fit / truth | p meas / model | iter | LM runs + search runs | wall / CPU s |");
  std::puts("|---|---|---|---|---|---|---|---|---|---|---|---|");
  // Trial t: seeds[t], K = ks[t % size]; the trials are shared out to `jobs` threads
  // (each fit single-threaded) and tallied in trial order.
  std::vector<Outcome> outcomes(static_cast<std::size_t>(trials));
  std::atomic<int> next{0};
  std::mutex print;
  std::exception_ptr failure;
  const auto work = [&] {
    for (int t = next++; t < trials; t = next++) {
      RigSpec spec = base;
      spec.seed = seeds[static_cast<std::size_t>(t)];
      spec.den_hartog_k = ks[static_cast<std::size_t>(t) % ks.size()];
      try {
        outcomes[static_cast<std::size_t>(t)] = run_trial(spec, print);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(print);
        failure = std::current_exception();
        next = trials;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < jobs; ++j) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
  std::vector<Tally> per_k(ks.size());
  Tally all;
  for (int t = 0; t < trials; ++t) {
    add_trial(per_k[static_cast<std::size_t>(t) % ks.size()],
              outcomes[static_cast<std::size_t>(t)]);
    add_trial(all, outcomes[static_cast<std::size_t>(t)]);
  }
  std::puts("");
  std::puts(
      "| K | trials | within 2/2/3/3 % k / b / F_fk / F_fs | worst \\|error\\| | 95 % intervals "
      "covering the truth | mean 95 % half-width | residual above the truth's | largest "
      "Cramer-Rao sd of F_fs | CPU s per fit, median / max |");
  std::puts("|---|---|---|---|---|---|---|---|---|");
  for (std::size_t i = 0; i < ks.size(); ++i)
    if (per_k[i].trials > 0) std::puts(summary_row(fmt::format("{:.2g}", ks[i]), per_k[i]).c_str());
  std::puts(summary_row("all", all).c_str());
  const char* names[4] = {"k", "b", "F_fk", "F_fs"};
  bool coverage_ok = true;
  std::string summary =
      fmt::format("{} trials, {} outside the tolerances (2/2/3/3 %);", all.trials, all.failures);
  for (int i = 0; i < 4; ++i) {
    const double coverage = static_cast<double>(all.covered[i]) / all.trials;
    coverage_ok = coverage_ok && coverage >= min_coverage;
    summary += fmt::format(" {}: coverage {}/{}", names[i], all.covered[i], all.trials);
  }
  summary += "; HAC coverage:";
  for (int i = 0; i < 4; ++i)
    summary += fmt::format(" {} {}/{}", names[i], all.covered_hac[i], all.trials);
  std::puts(summary.c_str());
  return all.failures == 0 && coverage_ok ? 0 : 1;
}

constexpr const char* kUsage =
    "usage: stickslip_fit_validation [--trials N] [--first-seed S | --seeds S1,S2,...]\n"
    "                                [--K K1,K2,...] [--duration S]\n"
    "                                [--min-coverage C] [--travel] [--floor-noise A] [--jobs J]\n"
    "       stickslip_fit_validation --write-rig FILE [--seed S] [--K K] [--duration S]\n"
    "                                [--shift-samples N] [--ax-in-g] [--unit-header] [--no-ax]\n"
    "                                [--travel] [--static-ratio R]\n"
    "Trials: seed S+t (or the t-th of --seeds), K cycling through the list. One row per fit\n"
    "(errors, 95 % intervals, the Cramer-Rao standard deviations from the Jacobian at the truth,\n"
    "the residual RMS of the fit and of the truth), then a table per K and over all trials.\n"
    "Exit status 1 when an estimate is outside its tolerance (k, b 2 %; F_fk, F_fs 3 %) or a\n"
    "coverage is below C (default 0.9). --travel adds the travel channel x_r (noise 3e-5 m) to\n"
    "the rig and the fit. --jobs J: J fits at once on threads (the CPU s are per fit).\n";

}  // namespace

int main(int argc, char** argv) {
  RigSpec spec;
  WriteOptions write;
  const char* rig_path = nullptr;
  std::vector<double> ks = {0.3, 0.6, 1.0, 1.5};
  int trials = 8;
  std::uint64_t first_seed = 1;
  std::vector<std::uint64_t> seeds;
  double min_coverage = 0.9;
  int jobs = 1;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--trials") && has_value) {
      trials = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--first-seed") && has_value) {
      first_seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (!std::strcmp(argv[i], "--seeds") && has_value) {
      for (double seed : parse_list(argv[++i])) seeds.push_back(static_cast<std::uint64_t>(seed));
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
    } else if (!std::strcmp(argv[i], "--jobs") && has_value) {
      jobs = std::atoi(argv[++i]);
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
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else {
      std::fprintf(stderr, "stickslip_fit_validation: unknown or incomplete option '%s'\n",
                   argv[i]);
      return 2;
    }
  }
  if (ks.empty() || trials < 1 || jobs < 1) {
    std::fputs("stickslip_fit_validation: --K needs values, --trials and --jobs >= 1\n", stderr);
    return 2;
  }
  try {
    if (rig_path != nullptr) return write_rig(rig_path, make_rig(spec, truth_for(spec)), write);
    if (seeds.empty())
      for (int t = 0; t < trials; ++t) seeds.push_back(first_seed + static_cast<std::uint64_t>(t));
    return run_trials(spec, ks, seeds, min_coverage, jobs);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "stickslip_fit_validation: %s\n", error.what());
    return 1;
  }
}
