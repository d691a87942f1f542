// `stickslip simulate --integrator reference`: the reference solver behind the command, with the
// same columns and statistics as every other integrator, and double only.
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;
using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

TEST_GROUP(SimulateWithReferenceIntegrator) {
  TempDir dir;
  GeneratorSpec spec;
  void setup() override {
    CHECK_TRUE(dir.ok());
    spec.kind = SignalKind::lorry;
    spec.rms_m_per_s2 = 0.35;
    spec.duration_s = 5.0;
    spec.dt_s = 1e-3;
    spec.seed = 1;
    write_generated_csv(spec, dir.file("in.csv"));
  }
  std::vector<std::string> simulate(const std::string& model) {
    return {"simulate",
            "--input",
            dir.file("in.csv"),
            "--output",
            dir.file("out.csv"),
            "--stats",
            dir.file("stats.json"),
            "--model",
            model,
            "--ffk",
            "40",
            "--ffs",
            "48",
            "--x0",
            "0.001",
            "--integrator",
            "reference",
            "--repetitions",
            "1"};
  }
};

// The rows are exactly solve_reference()'s trace (t and a_u echoed), and the statistics are
// computed from it: p from the exact stuck time, events counted, integrator named "reference".
TEST(SimulateWithReferenceIntegrator, WritesTheReferenceTraceAndItsStatistics) {
  for (const char* model : {"stick-slip", "stribeck", "signum", "smooth", "linear"}) {
    const CliRun run = run_stickslip(simulate(model));
    LONGS_EQUAL(0, run.status);
    STRCMP_EQUAL("", run.err.c_str());
    const auto table = stickslip::test::read_table(dir.file("out.csv"));
    CHECK(table.ok);
    STRCMP_EQUAL(
        "t,a_u,x_r,v_r,a_x,f_f,stuck",
        stickslip::test::split_lines(stickslip::test::read_text(dir.file("out.csv")))[0].c_str());

    OscillatorParams p;
    CHECK(parse_model(model, p.model));
    p.kinetic_friction_n = 40.0;
    p.static_friction_n = 48.0;
    p.dt_s = 1e-3;
    const std::vector<double> a_u = generate_signal(spec);
    const ReferenceTrace r = solve_reference(p, a_u, 0.001, 0.0);
    LONGS_EQUAL(static_cast<long>(a_u.size()), static_cast<long>(table.rows.size()));
    for (std::size_t n = 0; n < a_u.size(); ++n) {
      const auto& row = table.rows[n];
      CHECK(stickslip::test::bit_equal(a_u[n], row[1]));
      CHECK(stickslip::test::bit_equal(r.x_r_m[n], row[2]));
      CHECK(stickslip::test::bit_equal(r.v_r_m_per_s[n], row[3]));
      CHECK(stickslip::test::bit_equal(r.a_x_m_per_s2[n], row[4]));
      CHECK(stickslip::test::bit_equal(r.friction_n[n], row[5]));
      CHECK_EQUAL(static_cast<double>(r.stuck[n]), row[6]);
    }
    const auto stats = nlohmann::json::parse(stickslip::test::read_text(dir.file("stats.json")));
    CHECK(stats == nlohmann::json::parse(stickslip::test::split_lines(run.out).back()));
    STRCMP_EQUAL("reference", stats["integrator"].get<std::string>().c_str());
    STRCMP_EQUAL(model, stats["model"].get<std::string>().c_str());
    DOUBLES_EQUAL(r.stuck_time_s / 5.0, stats["p_stick"].get<double>(), 1e-15);
    LONGS_EQUAL(static_cast<long>(r.events), stats["events"].get<long>());
    CHECK(stats["ns_per_sample"].get<double>() > 0.0);
    double sum_u = 0.0, sum_x = 0.0;
    for (std::size_t n = 0; n < a_u.size(); ++n) {
      sum_u += a_u[n] * a_u[n];
      sum_x += r.a_x_m_per_s2[n] * r.a_x_m_per_s2[n];
    }
    DOUBLES_EQUAL(std::sqrt(sum_x / sum_u), stats["T_ax"].get<double>(), 1e-12);
  }
}

// The solver works in (long) double: a float run is refused up front, with nothing written.
TEST(SimulateWithReferenceIntegrator, RefusesScalarFloat) {
  std::vector<std::string> arguments = simulate("stick-slip");
  arguments.push_back("--scalar");
  arguments.push_back("float");
  const CliRun run = run_stickslip(arguments);
  LONGS_EQUAL(2, run.status);
  STRCMP_EQUAL(
      "stickslip: --scalar float: the reference integrator runs in double only (long double "
      "inside); use --scalar double\n",
      run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
  CHECK_FALSE(stickslip::test::exists(dir.file("stats.json")));
}

// Parameters the core refuses are refused the same way (the core's message, the option named).
TEST(SimulateWithReferenceIntegrator, RefusesWhatTheCoreRefuses) {
  std::vector<std::string> arguments = simulate("stick-slip");
  arguments.push_back("--mass");
  arguments.push_back("-3");
  const CliRun run = run_stickslip(arguments);
  LONGS_EQUAL(2, run.status);  // a value out of range on the command line: a usage error
  STRCMP_CONTAINS("stickslip: --mass: mass_kg: must be >= 1e-06", run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
}
