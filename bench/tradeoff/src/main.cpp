// stickslip_tradeoff: the speed-vs-accuracy harness. A thin command line over the tradeoff library:
//   run                 references, traces, timing and Odeint peers -> CSV
//   count-instructions  the streaming loops once under callgrind (instructions per sample)
//   report              docs/PERFORMANCE.md and the plot data from the CSV
//   build-info          compiler, flags and reference method compiled in
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "stickslip/host/error.hpp"
#include "tradeoff/combinations.hpp"
#include "tradeoff/measure.hpp"
#include "tradeoff/reference.hpp"
#include "tradeoff/report.hpp"
#include "tradeoff/runner.hpp"

namespace {

using namespace stickslip;
using namespace stickslip::tradeoff;

// The plan as the command line spells it; turned into a Plan (and checked) after parsing.
struct PlanText {
  std::string kinds = "wideband,lorry,harmonic";
  std::string frictions = "none,coulomb,stribeck";
  std::string ks = "0.2,0.8,1.5";
  std::string dampings = "504,0";
  std::string models =
      "linear,signum,smooth-tanh,smooth-atan,smooth-erf,smooth-rational,stick-slip,stribeck";
  std::string integrators = "euler,symplectic,rk4,exact";
  std::string scalars = "float,double";
  std::string dts = "0.1,0.25,0.5,1,2,5,10";
  std::string other_laws_dts = "1";
  std::string peers = "rk4,dopri5,dopri5-events";
  std::string tolerances = "1e-3,1e-6,1e-9";
  double duration_s = 20.0;
  int repetitions = 5;
  int peer_repetitions = 3;
  double min_repetition_ms = 2.0;
  std::size_t instruction_steps = 4000;
};

void add_plan_options(CLI::App* app, PlanText& t) {
  app->add_option("--kinds", t.kinds, "scene excitations: wideband, lorry, harmonic")
      ->capture_default_str();
  app->add_option("--frictions", t.frictions, "scene physics: none, coulomb, stribeck")
      ->capture_default_str();
  app->add_option("--K", t.ks, "Den Hartog factors of the friction scenes")->capture_default_str();
  app->add_option("--damping", t.dampings, "dampers b, N s/m")->capture_default_str();
  app->add_option("--duration", t.duration_s, "scene length, s")->capture_default_str();
  app->add_option("--models", t.models,
                  "linear, signum, smooth-tanh (smooth), smooth-atan, smooth-erf, smooth-rational, "
                  "stick-slip, stribeck")
      ->capture_default_str();
  app->add_option("--integrators", t.integrators, "euler, symplectic, rk4, exact")
      ->capture_default_str();
  app->add_option("--scalars", t.scalars, "float, double")->capture_default_str();
  app->add_option("--dt", t.dts, "steps in ms, whole multiples of 0.05 ms")->capture_default_str();
  app->add_option("--other-laws-dt", t.other_laws_dts,
                  "dt (ms) at which smooth-atan, -erf and -rational run")
      ->capture_default_str();
}

Plan make_plan(const PlanText& t) {
  Plan plan;
  plan.scenes.kinds = parse_kinds(t.kinds);
  plan.scenes.frictions = parse_frictions(t.frictions);
  plan.scenes.den_hartog_ks = parse_numbers("--K", t.ks, 0.0, false);
  plan.scenes.dampings_ns_per_m = parse_numbers("--damping", t.dampings, 0.0, true);
  if (!(t.duration_s > 0.0) || t.duration_s > 3600.0) {
    throw host::UsageError("--duration: must be > 0 and <= 3600 s");
  }
  plan.scenes.duration_s = t.duration_s;
  plan.models = parse_models(t.models);
  plan.integrators = parse_integrators(t.integrators);
  plan.scalars = parse_scalars(t.scalars);
  plan.dts_ms = parse_dts_ms(t.dts);
  plan.other_laws_dts_ms = parse_dts_ms(t.other_laws_dts);
  plan.peers = parse_peers(t.peers, parse_numbers("--tolerances", t.tolerances, 0.0, false));
  if (t.repetitions < 1 || t.peer_repetitions < 1)
    throw host::UsageError("--repetitions: must be >= 1");
  plan.timing.repetitions = t.repetitions;
  plan.timing.min_repetition_s = t.min_repetition_ms * 1e-3;
  plan.peer_timing.repetitions = t.peer_repetitions;
  plan.peer_timing.min_repetition_s = t.min_repetition_ms * 1e-3;
  plan.instruction_steps = t.instruction_steps;
  return plan;
}

// The run subcommand: the plan, the peers and timing, where the counts come from, the CSV.
CLI::App* add_run_command(CLI::App& app, PlanText& run_text, RunRequest& run_request) {
  CLI::App* run = app.add_subcommand("run", "Measure cost and error of every combination -> CSV");
  add_plan_options(run, run_text);
  run->add_option("--peers", run_text.peers, "rk4, dopri5, dopri5-events, or none")
      ->capture_default_str();
  run->add_option("--tolerances", run_text.tolerances, "error tolerances of the dopri5 peers")
      ->capture_default_str();
  run->add_option("--repetitions", run_text.repetitions,
                  "timed repetitions per combination (median)")
      ->capture_default_str();
  run->add_option("--peer-repetitions", run_text.peer_repetitions, "timed repetitions per peer run")
      ->capture_default_str();
  run->add_option("--min-repetition-ms", run_text.min_repetition_ms,
                  "a repetition loops over the input for at least this long")
      ->capture_default_str();
  run->add_option(
      "--instructions", run_request.instructions_dir,
      "directory of count-instructions' callgrind dumps (fills instructions_per_sample)");
  run->add_option("--output", run_request.output_csv, "CSV to write")->required();
  return run;
}

// The report subcommand: the inputs the report script gathered and where the outputs go.
CLI::App* add_report_command(CLI::App& app, ReportRequest& report_request) {
  CLI::App* report =
      app.add_subcommand("report", "Write PERFORMANCE.md and the plot data from the CSV");
  report->add_option("--results", report_request.results_csv, "the run's CSV")->required();
  report->add_option("--results-link", report_request.results_link, "link to the CSV from the .md")
      ->required();
  report->add_option("--machine", report_request.machine_file, "machine facts, 'key: value' lines")
      ->required();
  report->add_option("--profile-dump", report_request.profile_dump,
                     "callgrind dump of the headline configuration (count-instructions --steps 0)");
  report->add_option("--bench-step", report_request.bench_step_text,
                     "stickslip_bench_step console output");
  report->add_option("--bench-step-json", report_request.bench_step_json,
                     "the same run's --benchmark_out JSON (batch vs singles)");
  report->add_option(
      "--batch-profile", report_request.batch_profile_dir,
      "callgrind profiles of batch and singles (<tag>.json + <tag>.txt per benchmark)");
  report->add_option("--bench-step-avx2-json", report_request.bench_step_avx2_json,
                     "batch vs singles of a build with -march=x86-64-v3 (--benchmark_out JSON)");
  report->add_option("--bench-estimator-json", report_request.bench_estimator_json,
                     "stickslip_bench_state_estimator's --benchmark_out JSON");
  report->add_option("--output", report_request.output_md, "markdown to write")->required();
  report->add_option("--plot-dir", report_request.plot_dir, "where the gnuplot data go")
      ->required();
  report->add_option("--image-link", report_request.image_link, "PNG directory relative to the .md")
      ->required();
  report->add_option("--command", report_request.command, "the command that reproduces the report")
      ->required();
  report->add_option("--elapsed", report_request.elapsed_s, "seconds the command took so far");
  return report;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stickslip_tradeoff: speed vs accuracy of every model x integrator x scalar x dt "
      "against the reference solver, with Boost.Odeint peers"};
  app.require_subcommand(1);

  PlanText run_text;
  RunRequest run_request;
  CLI::App* run = add_run_command(app, run_text, run_request);

  PlanText count_text;
  CLI::App* count = app.add_subcommand(
      "count-instructions",
      "Run every combination's loop once on a short input with callgrind instrumentation; use "
      "under valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file=DIR/cg.%p");
  add_plan_options(count, count_text);
  count
      ->add_option("--steps", count_text.instruction_steps,
                   "steps per combination (0: the whole input)")
      ->capture_default_str();

  ReportRequest report_request;
  CLI::App* report = add_report_command(app, report_request);

  std::string estimator_json;
  CLI::App* estimator_section = app.add_subcommand(
      "estimator-section",
      "Print the report's state estimator section (as report writes it into PERFORMANCE.md) "
      "from stickslip_bench_state_estimator's --benchmark_out JSON");
  estimator_section->add_option("--bench-estimator-json", estimator_json, "the benchmark's JSON")
      ->required();

  CLI::App* info =
      app.add_subcommand("build-info", "Print compiler, flags, build type, reference method");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  try {
    if (*run) {
      run_request.plan = make_plan(run_text);
      run_harness(run_request, std::cerr);
    } else if (*count) {
      count_instructions(make_plan(count_text), std::cerr);
    } else if (*report) {
      write_report(report_request);
    } else if (*estimator_section) {
      write_estimator_section(std::cout, estimator_json);
    } else if (*info) {
      std::cout << "compiler: " << build_compiler() << "\nbuild type: " << build_type()
                << "\nflags: " << build_flags() << "\nreference: " << reference_method() << "\n";
    }
  } catch (const host::UsageError& error) {
    std::cerr << "stickslip_tradeoff: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "stickslip_tradeoff: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
