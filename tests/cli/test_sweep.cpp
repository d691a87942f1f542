// stickslip sweep and merge (sweep.hpp): each point is the simulation simulate runs, results do
// not depend on threads, batching or sharding, K scaling behaves as the physics says, and merge
// rebuilds the single-run file byte for byte and refuses incomplete or mixed shard sets.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/host/run/sweep.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;
using stickslip::test::CliRun;
using stickslip::test::read_text;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

void generate(const std::string& kind, double duration, const std::string& path) {
  const CliRun run =
      run_stickslip({"generate", "--kind", kind, "--rms", "0.35", "--duration",
                     std::to_string(duration), "--dt", "0.001", "--seed", "3", "--output", path});
  LONGS_EQUAL(0, run.status);
}

}  // namespace

TEST_GROUP(Sweep) {
  TempDir dir;
  std::string wideband, lorry;
  void setup() override {
    CHECK_TRUE(dir.ok());
    wideband = dir.file("wideband.csv");
    lorry = dir.file("lorry.csv");
    generate("wideband", 8.0, wideband);
    generate("lorry", 8.0, lorry);
  }
  SweepRequest request() const {
    SweepRequest r;
    r.inputs = {wideband, lorry};
    r.methods = {parse_sweep_method("signum:euler"), parse_sweep_method("stick-slip"),
                 parse_sweep_method("stick-slip:rk4")};
    r.damping_ns_per_m = {504.0, 200.0};
    r.k_values = {0.0, 0.3, 0.6, 0.9, 1.2, 1.5};
    return r;
  }
};

// Every row is exactly what simulate_signal gives for that point's parameters.
TEST(Sweep, EachPointIsTheSimulationOfItsParameters) {
  SweepRequest r = request();
  const std::vector<SweepRow> rows = compute_sweep(r);
  LONGS_EQUAL(2 * 2 * 3 * 6, rows.size());
  const SampledSignal lorry_signal = read_signal_csv(lorry);
  int checked = 0;
  for (const SweepRow& row : rows) {
    LONGS_EQUAL(checked, row.point);
    ++checked;
    if (row.input != lorry) continue;
    SimulationSetup setup;
    const auto colon = row.method.find(':');
    CHECK_TRUE(parse_model(row.method.substr(0, colon).c_str(), setup.params.model));
    CHECK_TRUE(parse_integrator(row.method.substr(colon + 1).c_str(), setup.params.integrator));
    setup.params.damping_ns_per_m = row.damping_ns_per_m;
    setup.params.kinetic_friction_n = setup.params.static_friction_n = row.friction_n;
    setup.params.dt_s = lorry_signal.dt_s;
    setup.repetitions = 1;
    SimulationTrace<double> trace;
    const SimulationSummary s = simulate_signal(setup, lorry_signal.a_u_m_per_s2, trace);
    CHECK_TRUE(stickslip::test::bit_equal(s.transmissibility, row.transmissibility));
    CHECK_TRUE(stickslip::test::bit_equal(s.stick_probability, row.stick_probability));
    CHECK_TRUE(stickslip::test::bit_equal(s.rms_x, row.rms_x));
    LONGS_EQUAL(s.events, row.events);
    // F_fk = K pi sqrt(2) m a0u / 4 reproduces the requested K.
    DOUBLES_EQUAL(row.k_target, row.k, 1e-12);
  }
}

// Threads, the SoA batch and the order of work change nothing in the file.
TEST(Sweep, OutputIsTheSameForAnyThreadCountAndWithoutBatch) {
  SweepRequest r = request();
  r.threads = 1;
  r.batch = false;
  run_sweep(r, dir.file("serial.csv"));
  r.threads = 5;
  r.batch = true;
  const SweepSummary summary = run_sweep(r, dir.file("parallel.csv"));
  LONGS_EQUAL(5, summary.threads);
  LONGS_EQUAL(72, summary.points_run);
  LONGS_EQUAL(72 * 8000, summary.samples);
  const std::string serial = read_text(dir.file("serial.csv"));
  CHECK_TRUE(serial.size() > 1000);
  CHECK_TRUE(serial == read_text(dir.file("parallel.csv")));
}

// The Coulomb models are positively homogeneous (a_u -> s a_u, F -> s F gives x_r -> s x_r), so
// T_ax and p depend on K alone: scaling the excitation at a fixed F_fk gives the same figures as
// scaling F_fk at the recording's own level. The linear model does not see K at all.
TEST(Sweep, VaryingTheExcitationOrTheFrictionGivesTheSameFiguresAtTheSameK) {
  SweepRequest r = request();
  r.inputs = {lorry};
  r.methods = {parse_sweep_method("stick-slip:exact"), parse_sweep_method("signum:exact"),
               parse_sweep_method("linear")};
  r.k_values = {0.2, 0.7, 1.4};
  const std::vector<SweepRow> by_friction = compute_sweep(r);
  r.vary = SweepVariable::excitation;
  r.friction_n = 30.0;
  const std::vector<SweepRow> by_excitation = compute_sweep(r);
  LONGS_EQUAL(by_friction.size(), by_excitation.size());
  for (std::size_t i = 0; i < by_friction.size(); ++i) {
    const SweepRow& f = by_friction[i];
    const SweepRow& e = by_excitation[i];
    DOUBLES_EQUAL(30.0, e.friction_n, 0.0);
    DOUBLES_EQUAL(4.0 * 30.0 / (kPi * std::sqrt(2.0) * 88.4 * e.k_target), e.a0u, 1e-12);
    DOUBLES_EQUAL(f.k, e.k, 1e-12);
    DOUBLES_EQUAL(f.transmissibility, e.transmissibility, 1e-9);
    DOUBLES_EQUAL(f.stick_probability, e.stick_probability, 1e-9);
  }
  // Linear: identical T_ax at every K; stick-slip: p grows with K.
  DOUBLES_EQUAL(by_friction[6].transmissibility, by_friction[8].transmissibility, 1e-12);
  CHECK_TRUE(by_friction[0].stick_probability < by_friction[1].stick_probability);
  CHECK_TRUE(by_friction[1].stick_probability < by_friction[2].stick_probability);
}

TEST(Sweep, ShardsMergeIntoTheSingleRunByteForByte) {
  SweepRequest r = request();
  run_sweep(r, dir.file("single.csv"));
  std::vector<std::string> shards;
  std::uint64_t points = 0;
  for (unsigned i = 1; i <= 5; ++i) {
    r.shard_index = i;
    r.shard_count = 5;
    shards.push_back(dir.file("shard" + std::to_string(i) + ".csv"));
    points += run_sweep(r, shards.back()).points_run;
  }
  LONGS_EQUAL(72, points);
  const std::vector<std::string> reversed(shards.rbegin(), shards.rend());
  const CliRun merged = run_stickslip({"merge", reversed[0], reversed[1], reversed[2], reversed[3],
                                       reversed[4], "--output", dir.file("merged.csv")});
  LONGS_EQUAL(0, merged.status);
  CHECK_TRUE(read_text(dir.file("single.csv")) == read_text(dir.file("merged.csv")));
  // One shard of one (--shard 1/1) merges too.
  const CliRun whole = run_stickslip({"sweep", "--input", wideband, "--input", lorry, "--method",
                                      "signum:euler,stick-slip:exact,stick-slip:rk4", "--damping",
                                      "504,200", "--k", "0,0.3,0.6,0.9,1.2,1.5", "--shard", "1/1",
                                      "--quiet", "--output", dir.file("one.csv")});
  LONGS_EQUAL(0, whole.status);
  LONGS_EQUAL(
      0,
      run_stickslip({"merge", dir.file("one.csv"), "--output", dir.file("one-merged.csv")}).status);
  CHECK_TRUE(read_text(dir.file("single.csv")) == read_text(dir.file("one-merged.csv")));

  // Missing shard, a shard twice, a shard of another sweep, a duplicated row: refused, no file.
  const auto merge = [&](const std::vector<std::string>& files) {
    std::vector<std::string> arguments{"merge"};
    arguments.insert(arguments.end(), files.begin(), files.end());
    arguments.insert(arguments.end(), {"--output", dir.file("bad.csv")});
    return run_stickslip(arguments);
  };
  CliRun run = merge({shards[0], shards[1], shards[2], shards[3]});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("shard 5/5 is missing", run.err.c_str());
  run = merge({shards[0], shards[1], shards[2], shards[3], shards[3]});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("given twice", run.err.c_str());
  SweepRequest other = request();
  other.k_values = {0.1};
  other.shard_index = 5;
  other.shard_count = 5;
  run_sweep(other, dir.file("other.csv"));
  run = merge({shards[0], shards[1], shards[2], shards[3], dir.file("other.csv")});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("shard of another sweep", run.err.c_str());
  std::string text = read_text(shards[4]);
  const std::vector<std::string> lines = stickslip::test::split_lines(text);
  stickslip::test::write_text(dir.file("dup.csv"), text + lines.back() + "\n");
  run = merge({shards[0], shards[1], shards[2], shards[3], dir.file("dup.csv")});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("appears twice", run.err.c_str());
  // A row dropped from a shard: the point is named.
  std::string shortened;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) shortened += lines[i] + "\n";
  stickslip::test::write_text(dir.file("short.csv"), shortened);
  run = merge({shards[0], shards[1], shards[2], shards[3], dir.file("short.csv")});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("is missing", run.err.c_str());
  // ... with the shard file that should hold it.
  STRCMP_CONTAINS((dir.file("short.csv") + ": point ").c_str(), run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("bad.csv")));
}

TEST(Sweep, CommandWritesCsvAndPlainProgressWhenNotATerminal) {
  const CliRun run =
      run_stickslip({"sweep", "--input", lorry, "--method", "stick-slip,signum:euler", "--damping",
                     "504", "--k-range", "0:1.5:11", "--output", dir.file("s.csv")});
  LONGS_EQUAL(0, run.status);
  STRCMP_CONTAINS("22 of 22 points", run.out.c_str());
  const std::vector<std::string> progress = stickslip::test::split_lines(run.err);
  CHECK_TRUE(progress.size() >= 2 && progress.size() <= 12);
  STRCMP_EQUAL("sweep: 22/22 points (100 %)", progress.back().c_str());
  CHECK_TRUE(run.err.find('\r') == std::string::npos);
  const std::vector<std::string> lines = stickslip::test::split_lines(read_text(dir.file("s.csv")));
  LONGS_EQUAL(23, lines.size());
  STRCMP_EQUAL(kSweepHeader, lines[0].c_str());

  std::ostringstream bar;
  const SweepProgress terminal = make_progress_reporter(bar, true);
  terminal(1, 4);
  terminal(4, 4);
  CHECK_TRUE(bar.str().find("\rsweep [##########") != std::string::npos);
  CHECK_TRUE(bar.str().find("] 4/4\n") != std::string::npos);
}

TEST(Sweep, BadRequestsAreUsageErrors) {
  struct Case {
    std::vector<std::string> extra;
    const char* message;
  };
  const Case cases[] = {
      {{"--k", "-1"}, "--k: must be >= 0"},
      {{"--k", "0", "--vary", "excitation"}, "--k: must be > 0"},
      {{"--k", "1", "--vary", "both"}, "--vary: expected friction or excitation"},
      {{"--k", "1", "--method", "coulomb"}, "--method: unknown model 'coulomb'"},
      {{"--k", "1", "--method", "signum:ode45"}, "--method: unknown integrator 'ode45'"},
      {{"--k", "1", "--shard", "5/4"}, "--shard: expected I/N"},
      {{"--k-range", "1:0:3"}, "--k-range: expected MIN:MAX:COUNT"},
      {{}, "--k: at least one K value"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> arguments{"sweep",    "--input",        lorry, "--damping", "504",
                                       "--output", dir.file("x.csv")};
    arguments.insert(arguments.end(), c.extra.begin(), c.extra.end());
    const CliRun run = run_stickslip(arguments);
    LONGS_EQUAL(2, run.status);
    STRCMP_CONTAINS(c.message, run.err.c_str());
    CHECK_FALSE(stickslip::test::exists(dir.file("x.csv")));
  }
  // Euler on an undamped spring: the point is named with the core's reason.
  const CliRun euler = run_stickslip({"sweep", "--input", lorry, "--damping", "0", "--k", "0.5",
                                      "--method", "signum:euler", "--output", dir.file("x.csv")});
  LONGS_EQUAL(2, euler.status);
  STRCMP_CONTAINS("point 0 (", euler.err.c_str());
  STRCMP_CONTAINS("explicit Euler", euler.err.c_str());
}
