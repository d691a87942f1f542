// Validation of the state estimator (observer/state_estimator.hpp) against an independent
// fine-step stick-slip simulation with drifting friction and noisy, biased, quantised sensors
// (tests/core/estimator_scenario.hpp): per seed and floor RMS, the errors and convergence times
// as a Markdown table, and optionally a trace of one run for the plots of docs/IDENTIFICATION.md.
//
//   stickslip_estimator_validation [--seeds N] [--kinetic F_N] [--static F_N] [--trace FILE]
//                                  [--trace-rms R] [--trace-seed S]
// (--kinetic, --static: the truth's friction levels at t = 0; default 60 and 70 N.)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/estimator_scenario.hpp"

using namespace stickslip;
using namespace stickslip::test;

namespace {

const char* sensors_name(Sensors s) {
  switch (s) {
    case Sensors::acceleration_and_travel:
      return "a_x + travel";
    case Sensors::acceleration_only:
      return "a_x only";
    case Sensors::travel_only:
      return "travel only";
  }
  return "?";
}

bool write_trace(const char* path, const std::vector<TraceRow>& rows) {
  std::FILE* f = std::fopen(path, "w");
  if (!f) return false;
  std::fprintf(f,
               "# t_s v_r v_hat x_r x_hat F_f F_f_hat F_fk F_fk_hat F_fs F_fs_hat stuck "
               "stuck_hat\n");
  for (const TraceRow& r : rows) {
    std::fprintf(f, "%.4f %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %d %d\n", r.t_s, r.v_r,
                 r.v_hat, r.x_r, r.x_hat, r.friction, r.friction_hat, r.kinetic, r.kinetic_hat,
                 r.fstatic, r.static_hat, r.stuck ? 1 : 0, r.stuck_hat ? 1 : 0);
  }
  return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  const char* trace_path = nullptr;
  double trace_rms = 0.5;
  unsigned trace_seed = 1;
  EstimatorScenario base;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--kinetic") && i + 1 < argc) {
      base.kinetic_friction_n = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--static") && i + 1 < argc) {
      base.static_friction_n = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--trace") && i + 1 < argc) {
      trace_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--trace-rms") && i + 1 < argc) {
      trace_rms = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--trace-seed") && i + 1 < argc) {
      trace_seed = unsigned(std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr,
                   "usage: %s [--seeds N] [--trace FILE] [--trace-rms R] [--trace-seed S]\n",
                   argv[0]);
      return 2;
    }
  }
  std::printf(
      "| sensors | floor RMS | seed | stuck share | v_r err / RMS v_r | x_r RMS err (mm) | F_f RMS "
      "err / F_fk (t>10 s) | F_f conv. (s) | max F_fk err (t>=20 s) | F_fk conv. (s) | F_fk end "
      "| F_fs end | stuck agreement |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const double levels[] = {0.35, 0.6, 1.0};
  const Sensors kinds[] = {Sensors::acceleration_and_travel, Sensors::acceleration_only,
                           Sensors::travel_only};
  for (Sensors kind : kinds) {
    for (double rms : levels) {
      for (int seed = 1; seed <= seeds; ++seed) {
        EstimatorScenario sc = base;
        sc.seed = std::uint64_t(seed);
        sc.floor_rms_m_per_s2 = rms;
        const std::vector<ScenarioSample> samples = make_scenario(sc);
        const EstimatorErrors e = run_estimator<double>(samples, estimator_params(sc), kind);
        // A convergence time at the run's end means "not within the run".
        char f_conv[32], k_conv[32];
        const double last = sc.duration_s - 1.0;
        std::snprintf(f_conv, sizeof f_conv, "%.1f", e.friction_convergence_s);
        std::snprintf(k_conv, sizeof k_conv, "%.1f", e.kinetic_convergence_s);
        std::printf(
            "| %s | %.2f | %d | %.2f | %.1f %% | %.3f | %.1f %% | %s | %.1f %% | %s | %+.1f %% "
            "| %+.1f %% | %.3f |\n",
            sensors_name(kind), rms, seed, e.stick_share, 100 * e.v_r_rms_relative,
            1e3 * e.x_r_rms_m, 100 * e.friction_rms_relative,
            e.friction_convergence_s >= last ? "never" : f_conv, 100 * e.kinetic_max_relative,
            e.kinetic_convergence_s >= last ? "never" : k_conv, 100 * e.kinetic_final_relative,
            100 * e.static_final_relative, e.stuck_agreement);
      }
    }
  }
  if (trace_path) {
    EstimatorScenario sc = base;
    sc.seed = trace_seed;
    sc.floor_rms_m_per_s2 = trace_rms;
    std::vector<TraceRow> rows;
    run_estimator<double>(make_scenario(sc), estimator_params(sc), Sensors::acceleration_and_travel,
                          &rows, 1);
    if (!write_trace(trace_path, rows)) {
      std::fprintf(stderr, "%s: cannot write\n", trace_path);
      return 1;
    }
  }
  return 0;
}
