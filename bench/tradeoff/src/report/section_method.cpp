#include <cmath>
#include <set>
#include <string>

#include <fmt/format.h>

#include "report/sections.hpp"
#include "report/text.hpp"

namespace stickslip::tradeoff::report {
namespace {

// The scenes and runs of this run.
void method_coverage(std::ostream& md, const Results& results) {
  const Row& first = results.rows.front();
  const auto distinct = [&](auto member, auto keep) {
    std::set<std::string> out;
    for (const Row& r : results.rows) {
      if (keep(r)) out.insert(member(r));
    }
    std::string text;
    for (const std::string& item : out) text += (text.empty() ? "" : ", ") + item;
    return text.empty() ? std::string("none") : text;
  };
  const auto distinct_numbers = [&](auto member, auto keep) {
    std::set<double> out;
    for (const Row& r : results.rows) {
      if (keep(r)) out.insert(member(r));
    }
    std::string text;
    for (const double item : out) text += (text.empty() ? "" : ", ") + fmt::format("{:g}", item);
    return text.empty() ? std::string("none") : text;
  };
  const auto any = [](const Row&) { return true; };
  md << fmt::format(
      "- **Scenes** ({}): excitations {} (wideband 0.5–20 Hz; lorry-like; harmonic at 1.8 Hz, the "
      "resonance "
      "is 1.82 Hz), RMS a0u = 0.35 m/s^2, {:g} s each; m = 88.4 kg, k = 11500 N/m, b in {{{}}} N "
      "s/m. "
      "Coulomb scenes: F_fs = F_fk from K = 4 F_fk/(pi sqrt(2) m a0u), K in {{{}}}; Stribeck "
      "scenes: "
      "F_fs = 1.3 F_fk, v_S = 0.01 m/s; frictionless scenes for the linear model. Names: "
      "`<excitation>-K<K>-b<b>`, `<excitation>-stribeck-K<K>-b<b>`, `<excitation>-linear-b<b>`.\n",
      results.scenes.size(), distinct([](const Row& r) { return r.kind; }, any), first.duration_s,
      distinct_numbers([](const Row& r) { return r.damping_ns_per_m; }, any),
      distinct_numbers([](const Row& r) { return r.den_hartog_k; },
                       [](const Row& r) { return r.friction != "none"; }));
  md << fmt::format(
      "- **Runs**: models {} (smooth-* with c = 1000 s/m; smooth-atan at dt {{{}}} ms only); "
      "integrators {}; "
      "scalars {}; dt {{{}}} ms; Boost.Odeint peers {}.\n",
      distinct([](const Row& r) { return r.model; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct_numbers([](const Row& r) { return r.dt_ms; },
                       [](const Row& r) { return r.model == "smooth-atan"; }),
      distinct([](const Row& r) { return r.integrator; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct([](const Row& r) { return r.scalar; },
               [](const Row& r) { return r.implementation == "stickslip"; }),
      distinct_numbers([](const Row& r) { return r.dt_ms; }, any),
      distinct([](const Row& r) { return r.configuration(); },
               [](const Row& r) { return r.implementation == "odeint"; }));
}

// How inputs, references, errors, cost and instructions are obtained.
void method_measurement(std::ostream& md, const Facts& facts) {
  md << "- **Input**: each excitation is generated once at 0.05 ms "
        "(`stickslip::host::generate_signal`, seed 1); "
        "the input at dt is every (dt/0.05 ms)-th sample, so a run and its reference see the same "
        "samples "
        "(first-order hold between them; float runs get them rounded to float).\n";
  md << "- **Reference**: `" << fact(facts, "reference")
     << "`, on the same sampled input at the same dt. *Error vs physics* compares with the scene's "
        "physically "
        "correct reference (stick-slip with F_fs = F_fk for signum, smooth and stick-slip — the "
        "exact Filippov "
        "solution of signum is stick-slip; Stribeck; linear); *solver error* with the model's own "
        "reference.\n";
  md << "- **Errors**: relative error of T_ax = RMS(a_x)/RMS(a_u), i.e. of RMS a_x (same input; "
        "the run's own "
        "running statistics, float runs in float); absolute error of the stick probability p "
        "(stuck time / "
        "total time; models with a stuck state only); RMS of the a_x and x_r history differences, "
        "relative "
        "to the reference's RMS here (absolute in the CSV).\n";
  md << "- **Cost**: the streaming loop only — `reset`, then `step()` and "
        "`RunningStatistics::add_sample/"
        "add_step` per sample, no I/O, no allocation, the model dispatched once outside the loop "
        "(the trace "
        "for the errors comes from a separate, untimed pass). A warm-up pass, then repetitions of "
        "at least "
        "2 ms each (whole passes over the input); the median ns per step is reported, the fastest "
        "and slowest "
        "repetitions are in the CSV.\n";
  md << fmt::format(
      "- **Instructions**: `perf stat -e instructions` is not supported on this machine. The "
      "harness runs "
      "once under `valgrind --tool=callgrind --collect-atstart=no` (`stickslip_tradeoff "
      "count-instructions`): "
      "each combination's loop runs over the first {} steps of its input between "
      "CALLGRIND_ZERO_STATS + "
      "CALLGRIND_TOGGLE_COLLECT and CALLGRIND_TOGGLE_COLLECT + "
      "CALLGRIND_DUMP_STATS_AT(\"<combination>#<steps>\"), "
      "and `run --instructions` reads the Ir totals from the dump files (our configurations; the "
      "peers are "
      "timed only). (START/STOP_INSTRUMENTATION with "
      "`--instr-atstart=no` gives the same counts but flushes the translation cache at every "
      "switch, which "
      "made the pass several times slower over thousands of combinations; `--collect-atstart=no` "
      "with "
      "START/STOP_INSTRUMENTATION alone counts nothing, collection stays off.)\n",
      fact(facts, "instruction steps"));
  md << "- **Status**: `refused: <parameter>` when `configure()` refuses, `unstable` when a run "
        "leaves any "
        "physical range (non-finite, |x_r| above 10x the reference's + 1 m, or RMS a_x above 100x "
        "the "
        "reference's + 10 m/s^2); neither gets error figures.\n\n";
}

}  // namespace

void section_reproduce(std::ostream& md, const ReportRequest& request, const Facts& facts) {
  md << "# Performance: speed vs accuracy\n\n"
        "<!-- Generated by tools/performance-report.sh (stickslip_tradeoff report): do not edit, "
        "re-run. -->\n\n";
  md << fmt::format("Measured {} on commit {}.\n\n", fact(facts, "date"), fact(facts, "commit"));

  // The marker keeps tests/docs/run_blocks.py from running the whole report inside CTest.
  md << "## Reproduce\n\n<!-- docs-test: skip reason=\"long report / set-up; run by CI itself\" "
        "-->\n```sh\n"
     << request.command << "\n```\n\n";
  md << "One command: installs what is missing (`tools/install-deps.sh --report`: gnuplot-nox, "
        "valgrind), "
        "configures and builds the `release` preset, counts instructions under callgrind, runs the "
        "harness "
        "(`stickslip_tradeoff run`), profiles the headline configuration, runs "
        "`stickslip_bench_step` if it "
        "is built, writes this file and draws the plots.";
  if (request.elapsed_s > 0.0) {
    md << fmt::format(
        " It took **{:.0f} min {:02.0f} s** on the machine below (up to writing this file).",
        std::floor(request.elapsed_s / 60.0), std::fmod(request.elapsed_s, 60.0));
  }
  md << "\n\n";
}

void section_machine(std::ostream& md, const Facts& facts) {
  md << "## Machine and build\n\n";
  Table machine;
  machine.header = {"", ""};
  machine.rows = {
      {"CPU", fact(facts, "cpu")},
      {"cores", fact(facts, "cores")},
      {"OS", fact(facts, "os")},
      {"compiler", fact(facts, "compiler")},
      {"build", "CMake `release` preset: " + fact(facts, "build type") + ", flags `" +
                    fact(facts, "flags") + "`"},
      {"reference", fact(facts, "reference")},
      {"load average (1 min) at the start / end of the timed run",
       fact(facts, "load before") + " / " + fact(facts, "load after") +
           " (the harness itself adds 1 on 2 cores; more means other processes shared the "
           "machine and disturbed the timings: the CSV keeps each run's fastest and slowest "
           "repetition too)"}};
  machine.write(md);
}

void section_method(std::ostream& md, const Results& results, const Facts& facts) {
  md << "## Method\n\n";
  method_coverage(md, results);
  method_measurement(md, facts);
}

}  // namespace stickslip::tradeoff::report
