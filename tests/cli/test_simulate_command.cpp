#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/models/scaled_oscillator.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::Table;
using stickslip::test::TempDir;

namespace {

const char* const kContractKeys[] = {"samples", "dt",      "rms_u", "rms_x",
                                     "T_ax",    "p_stick", "K",     "ns_per_sample"};

enum Column { kT, kAu, kXr, kVr, kAx, kFf, kStuck };

nlohmann::json last_line_json(const std::string& out) {
  const auto lines = stickslip::test::split_lines(out);
  return lines.empty() ? nlohmann::json() : nlohmann::json::parse(lines.back());
}

// Runs the oscillator in this process on the file's a_u, the way simulate is specified to, and
// checks every row of simulate's output bit for bit.
template <typename T>
void expect_output_equals_direct_run(const Table& table, const stickslip::OscillatorParams& params,
                                     double x0 = 0.0, double v0 = 0.0) {
  std::vector<T> a_u;
  for (const auto& row : table.rows) a_u.push_back(static_cast<T>(row[kAu]));
  stickslip::with_oscillator<T>(params, [&](auto& oscillator) {
    CHECK_TRUE(oscillator.configure(params).ok());
    oscillator.reset(static_cast<T>(x0), static_cast<T>(v0), a_u[0]);
    for (std::size_t n = 0; n < a_u.size(); ++n) {
      const stickslip::StepOutput<T> out = n == 0 ? oscillator.current() : oscillator.step(a_u[n]);
      const auto& row = table.rows[n];
      // The file holds each T exactly (as a double printed with %.17g).
      if (!(static_cast<T>(row[kXr]) == out.x_r_m && static_cast<T>(row[kVr]) == out.v_r_m_per_s &&
            static_cast<T>(row[kAx]) == out.a_x_m_per_s2 &&
            static_cast<T>(row[kFf]) == out.friction_n && row[kStuck] == (out.stuck ? 1.0 : 0.0))) {
        FAIL(("row " + std::to_string(n) + " differs from the direct run").c_str());
      }
    }
    return 0;
  });
}

}  // namespace

TEST_GROUP(SimulateCommand) {
  TempDir dir;
  std::string input;
  void setup() override {
    CHECK_TRUE(dir.ok());
    input = dir.file("lorry.csv");
    const CliRun run = run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "5", "--dt", "0.001", "--seed", "1", "--output", input});
    LONGS_EQUAL(0, run.status);
  }
  CliRun simulate(std::vector<std::string> extra) {
    std::vector<std::string> arguments{"simulate",
                                       "--input",
                                       input,
                                       "--output",
                                       dir.file("out.csv"),
                                       "--stats",
                                       dir.file("stats.json")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_stickslip(arguments);
  }
  stickslip::OscillatorParams params(stickslip::FrictionModel model, double friction_n) {
    stickslip::OscillatorParams p;  // the reference system
    p.model = model;
    p.integrator = stickslip::default_integrator(model);
    p.kinetic_friction_n = p.static_friction_n = friction_n;
    const Table table = stickslip::test::read_table(input);
    p.dt_s =
        (table.rows.back()[0] - table.rows.front()[0]) / static_cast<double>(table.rows.size() - 1);
    return p;
  }
};

TEST(SimulateCommand, WritesOneRowPerSampleWithTheContractHeader) {
  const CliRun run = simulate({"--model", "stick-slip", "--ffk", "45"});
  LONGS_EQUAL(0, run.status);
  STRCMP_EQUAL("", run.err.c_str());
  const auto lines = stickslip::test::split_lines(stickslip::test::read_text(dir.file("out.csv")));
  STRCMP_EQUAL("t,a_u,x_r,v_r,a_x,f_f,stuck", lines.at(0).c_str());
  const Table out = stickslip::test::read_table(dir.file("out.csv"));
  const Table in = stickslip::test::read_table(input);
  CHECK_TRUE(out.ok);
  LONGS_EQUAL(5001, out.rows.size());
  LONGS_EQUAL(in.rows.size(), out.rows.size());
  for (std::size_t n = 0; n < out.rows.size(); ++n) {
    LONGS_EQUAL(7, out.rows[n].size());
    // t and a_u echo the input exactly.
    CHECK_TRUE(stickslip::test::bit_equal(in.rows[n][0], out.rows[n][kT]));
    CHECK_TRUE(stickslip::test::bit_equal(in.rows[n][1], out.rows[n][kAu]));
    CHECK_TRUE(out.rows[n][kStuck] == 0.0 || out.rows[n][kStuck] == 1.0);
  }
}

TEST(SimulateCommand, FirstRowIsTheInitialState) {
  LONGS_EQUAL(
      0, simulate({"--model", "stick-slip", "--ffk", "45", "--x0", "0.002", "--v0", "0"}).status);
  const Table out = stickslip::test::read_table(dir.file("out.csv"));
  const auto p = params(stickslip::FrictionModel::stick_slip, 45.0);
  stickslip::Oscillator<double, stickslip::CoulombStickSlip> seat;
  CHECK_TRUE(seat.configure(p).ok());
  seat.reset(0.002, 0.0, out.rows[0][kAu]);
  const auto initial = seat.current();
  DOUBLES_EQUAL(0.002, out.rows[0][kXr], 0.0);
  DOUBLES_EQUAL(0.0, out.rows[0][kVr], 0.0);
  CHECK_TRUE(stickslip::test::bit_equal(initial.a_x_m_per_s2, out.rows[0][kAx]));
  CHECK_TRUE(stickslip::test::bit_equal(initial.friction_n, out.rows[0][kFf]));
  DOUBLES_EQUAL(initial.stuck ? 1.0 : 0.0, out.rows[0][kStuck], 0.0);
}

TEST(SimulateCommand, StatisticsAreTheLastStdoutLineAndTheStatsFile) {
  const CliRun run = simulate({"--model", "stick-slip", "--ffk", "45"});
  LONGS_EQUAL(0, run.status);
  const nlohmann::json stats = last_line_json(run.out);
  for (const char* key : kContractKeys) CHECK_TRUE(stats.contains(key));
  const auto lines = stickslip::test::split_lines(run.out);
  STRCMP_EQUAL((lines.back() + "\n").c_str(),
               stickslip::test::read_text(dir.file("stats.json")).c_str());
  LONGS_EQUAL(5001, stats["samples"].get<long>());
  DOUBLES_EQUAL(0.001, stats["dt"].get<double>(), 1e-15);
  STRCMP_EQUAL("stick-slip", stats["model"].get<std::string>().c_str());
  STRCMP_EQUAL("exact", stats["integrator"].get<std::string>().c_str());
  STRCMP_EQUAL("double", stats["scalar"].get<std::string>().c_str());
  DOUBLES_EQUAL(45.0, stats["ffs"].get<double>(), 0.0);  // --ffs defaults to --ffk

  // The figures agree with the written columns and with their definitions.
  const Table out = stickslip::test::read_table(dir.file("out.csv"));
  double sum_u = 0.0, sum_x = 0.0;
  for (const auto& row : out.rows) {
    sum_u += row[kAu] * row[kAu];
    sum_x += row[kAx] * row[kAx];
  }
  const double rms_u = std::sqrt(sum_u / static_cast<double>(out.rows.size()));
  const double rms_x = std::sqrt(sum_x / static_cast<double>(out.rows.size()));
  DOUBLES_EQUAL(rms_u, stats["rms_u"].get<double>(), 1e-12 * rms_u);
  DOUBLES_EQUAL(0.35, rms_u, 1e-12);
  DOUBLES_EQUAL(rms_x, stats["rms_x"].get<double>(), 1e-12 * rms_x);
  DOUBLES_EQUAL(rms_x / rms_u, stats["T_ax"].get<double>(), 1e-12);
  DOUBLES_EQUAL(stickslip::den_hartog_factor(45.0, 88.4, stats["rms_u"].get<double>()),
                stats["K"].get<double>(), 1e-15);
  const double p = stats["p_stick"].get<double>();
  CHECK_TRUE(p > 0.5 && p <= 1.0);  // K = 1.31: the seat sticks most of the time
  const double ns = stats["ns_per_sample"].get<double>();
  CHECK_TRUE(ns > 0.0 && ns < 1e6);
  LONGS_EQUAL(5, stats["repetitions"].get<int>());
  LONGS_EQUAL(0, stats["rejected_inputs"].get<int>());
}

TEST(SimulateCommand, OutputEqualsADirectRunBitForBitForEveryModel) {
  const stickslip::FrictionModel models[] = {
      stickslip::FrictionModel::linear, stickslip::FrictionModel::signum,
      stickslip::FrictionModel::smooth, stickslip::FrictionModel::stick_slip,
      stickslip::FrictionModel::stribeck};
  for (stickslip::FrictionModel model : models) {
    const CliRun run =
        simulate({"--model", stickslip::model_name(model), "--ffk", "45", "--repetitions", "1"});
    LONGS_EQUAL(0, run.status);
    const nlohmann::json stats = last_line_json(run.out);
    STRCMP_EQUAL(stickslip::integrator_name(stickslip::default_integrator(model)),
                 stats["integrator"].get<std::string>().c_str());
    const auto p = params(model, 45.0);
    DOUBLES_EQUAL(p.dt_s, stats["dt"].get<double>(), 0.0);
    expect_output_equals_direct_run<double>(stickslip::test::read_table(dir.file("out.csv")), p);
  }
}

TEST(SimulateCommand, FloatRunEqualsADirectFloatRunBitForBit) {
  const CliRun run = simulate({"--model", "stick-slip", "--ffk", "45", "--ffs", "60", "--scalar",
                               "float", "--repetitions", "3"});
  LONGS_EQUAL(0, run.status);
  STRCMP_EQUAL("float", last_line_json(run.out)["scalar"].get<std::string>().c_str());
  auto p = params(stickslip::FrictionModel::stick_slip, 45.0);
  p.static_friction_n = 60.0;
  expect_output_equals_direct_run<float>(stickslip::test::read_table(dir.file("out.csv")), p);
}

// --scalar fixed: every row equals a direct Oscillator<Fixed> run, converted to double (exact for
// these magnitudes), and the statistics say whether anything saturated.
TEST(SimulateCommand, FixedRunEqualsADirectFixedRunBitForBit) {
  const CliRun run = simulate({"--model", "stick-slip", "--ffk", "45", "--ffs", "60", "--scalar",
                               "fixed", "--repetitions", "1"});
  LONGS_EQUAL(0, run.status);
  const nlohmann::json stats = last_line_json(run.out);
  STRCMP_EQUAL("fixed", stats["scalar"].get<std::string>().c_str());
  CHECK_FALSE(stats["saturation"].get<bool>());
  LONGS_EQUAL(0, stats["saturated_steps"].get<long>());
  auto p = params(stickslip::FrictionModel::stick_slip, 45.0);
  p.static_friction_n = 60.0;
  const Table table = stickslip::test::read_table(dir.file("out.csv"));
  stickslip::Oscillator<stickslip::Fixed, stickslip::CoulombStickSlip> seat;
  CHECK_TRUE(seat.configure(p).ok());
  seat.reset(stickslip::Fixed(0), stickslip::Fixed(0), stickslip::Fixed(table.rows[0][kAu]));
  for (std::size_t n = 0; n < table.rows.size(); ++n) {
    const auto out = n == 0 ? seat.current() : seat.step(stickslip::Fixed(table.rows[n][kAu]));
    const auto& row = table.rows[n];
    if (!(row[kXr] == out.x_r_m.to_double() && row[kVr] == out.v_r_m_per_s.to_double() &&
          row[kAx] == out.a_x_m_per_s2.to_double() && row[kFf] == out.friction_n.to_double() &&
          row[kStuck] == (out.stuck ? 1.0 : 0.0))) {
      FAIL(("row " + std::to_string(n) + " differs from the direct fixed-point run").c_str());
    }
  }
  // Saturation is reported, not hidden: an input far beyond the checked range.
  stickslip::test::write_text(input, "t,a_u\n0,0\n0.001,200000\n0.002,200000\n0.003,0\n");
  const CliRun hard =
      simulate({"--model", "stick-slip", "--ffk", "45", "--scalar", "fixed", "--repetitions", "1"});
  LONGS_EQUAL(0, hard.status);
  CHECK_TRUE(last_line_json(hard.out)["saturation"].get<bool>());
  CHECK(last_line_json(hard.out)["saturated_steps"].get<long>() >= 1);
}

// --scalar fixed32: every row equals a direct ScaledOscillator<Fixed32> run with the outputs
// converted to SI; what the Q7.24 scaling cannot hold is refused by name, in scene units.
TEST(SimulateCommand, Fixed32RunEqualsADirectScaledRunBitForBit) {
  const CliRun run =
      simulate({"--model", "stick-slip", "--ffk", "45", "--ffs", "60", "--scalar", "fixed32",
                "--input-range", "32.768", "--displacement-range", "0.1", "--repetitions", "1"});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  const nlohmann::json stats = last_line_json(run.out);
  STRCMP_EQUAL("fixed32", stats["scalar"].get<std::string>().c_str());
  CHECK_FALSE(stats["saturation"].get<bool>());
  auto p = params(stickslip::FrictionModel::stick_slip, 45.0);
  p.static_friction_n = 60.0;
  p.input_range_m_per_s2 = 32.768;
  p.displacement_range_m = 0.1;
  const Table table = stickslip::test::read_table(dir.file("out.csv"));
  using stickslip::Fixed32;
  stickslip::ScaledOscillator<Fixed32, stickslip::CoulombStickSlip> seat;
  CHECK_TRUE(seat.configure(p).ok());
  seat.oscillator().reset(Fixed32(0), Fixed32(0), seat.acceleration(table.rows[0][kAu]));
  for (std::size_t n = 0; n < table.rows.size(); ++n) {
    const auto out =
        n == 0 ? seat.oscillator().current() : seat.step(seat.acceleration(table.rows[n][kAu]));
    const auto& row = table.rows[n];
    if (!(row[kXr] == seat.to_si_displacement(out.x_r_m) &&
          row[kVr] == seat.to_si_velocity(out.v_r_m_per_s) &&
          row[kAx] == seat.to_si_acceleration(out.a_x_m_per_s2) &&
          row[kFf] == seat.to_si_force(out.friction_n) && row[kStuck] == (out.stuck ? 1.0 : 0.0))) {
      FAIL(("row " + std::to_string(n) + " differs from the direct Q7.24 run").c_str());
    }
  }
  // The default 1 m stroke makes L = 31 mm: 45 N of friction is then below the resolution.
  const CliRun wide = simulate({"--model", "stick-slip", "--ffk", "45", "--scalar", "fixed32"});
  CHECK(wide.status != 0);
  CHECK_TEXT(wide.err.find("--ffk: kinetic_friction_n: in scene units") != std::string::npos,
             wide.err.c_str());
  const CliRun stribeck = simulate({"--model", "stribeck", "--ffk", "45", "--scalar", "fixed32"});
  CHECK(stribeck.status != 0);
  CHECK_TEXT(stribeck.err.find("--model: model: stribeck needs exp()") != std::string::npos,
             stribeck.err.c_str());
}

TEST(SimulateCommand, FixedRefusesWhatFixedPointDoesNotOfferByName) {
  const CliRun stribeck = simulate({"--model", "stribeck", "--ffk", "45", "--scalar", "fixed"});
  CHECK(stribeck.status != 0);
  CHECK_TEXT(stribeck.err.find("--model: model: stribeck needs exp()") != std::string::npos,
             stribeck.err.c_str());
  const CliRun tanh = simulate({"--model", "smooth", "--ffk", "45", "--scalar", "fixed"});
  CHECK(tanh.status != 0);
  CHECK_TEXT(tanh.err.find("--smoothing: smoothing: tanh") != std::string::npos, tanh.err.c_str());
  const CliRun stiff =
      simulate({"--model", "stick-slip", "--ffk", "45", "--stiffness", "5e6", "--scalar", "fixed"});
  CHECK(stiff.status != 0);
  CHECK_TEXT(stiff.err.find("--stiffness: stiffness_n_per_m: the stiffness k") != std::string::npos,
             stiff.err.c_str());
  const CliRun range = simulate(
      {"--model", "stick-slip", "--ffk", "45", "--scalar", "fixed", "--input-range", "1e5"});
  CHECK(range.status != 0);
  CHECK_TEXT(range.err.find("--input-range: input_range_m_per_s2: the input force m*a_u") !=
                 std::string::npos,
             range.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
}

TEST(SimulateCommand, OptionsReachTheModel) {
  const CliRun run = simulate(
      {"--model", "smooth", "--smoothing", "atan", "--smoothing-c", "200", "--integrator", "exact",
       "--mass",  "70",     "--stiffness", "9000", "--damping",     "300", "--ffk",        "20",
       "--x0",    "0.001",  "--v0",        "0.01", "--repetitions", "1"});
  LONGS_EQUAL(0, run.status);
  const nlohmann::json stats = last_line_json(run.out);
  STRCMP_EQUAL("exact", stats["integrator"].get<std::string>().c_str());
  STRCMP_EQUAL("atan", stats["smoothing"].get<std::string>().c_str());
  auto p = params(stickslip::FrictionModel::smooth, 20.0);
  p.smoothing = stickslip::SmoothingLaw::atan;
  p.smoothing_constant_s_per_m = 200.0;
  p.integrator = stickslip::Integrator::exact;
  p.mass_kg = 70.0;
  p.stiffness_n_per_m = 9000.0;
  p.damping_ns_per_m = 300.0;
  expect_output_equals_direct_run<double>(stickslip::test::read_table(dir.file("out.csv")), p,
                                          0.001, 0.01);
}

TEST(SimulateCommand, ReadsAHandWrittenFileWithExtraColumns) {
  stickslip::test::write_text(dir.file("hand.csv"),
                              "a_u,t,comment\n0.5,10.0,0\n-0.5,10.5,1\n0.25,11.0,2\n");
  const CliRun run = run_stickslip({"simulate", "--input", dir.file("hand.csv"), "--output",
                                    dir.file("hand-out.csv"), "--model", "linear"});
  LONGS_EQUAL(0, run.status);
  const nlohmann::json stats = last_line_json(run.out);
  LONGS_EQUAL(3, stats["samples"].get<int>());
  DOUBLES_EQUAL(0.5, stats["dt"].get<double>(), 0.0);
  DOUBLES_EQUAL(0.0, stats["K"].get<double>(), 0.0);  // no friction
  const Table out = stickslip::test::read_table(dir.file("hand-out.csv"));
  LONGS_EQUAL(3, out.rows.size());
  DOUBLES_EQUAL(10.5, out.rows[1][kT], 0.0);
  DOUBLES_EQUAL(-0.5, out.rows[1][kAu], 0.0);
}

TEST(SimulateCommand, NoExcitationGivesNullKRatherThanInfinity) {
  stickslip::test::write_text(dir.file("zero.csv"), "t,a_u\n0,0\n0.001,0\n0.002,0\n");
  const CliRun run =
      run_stickslip({"simulate", "--input", dir.file("zero.csv"), "--output",
                     dir.file("zero-out.csv"), "--model", "stick-slip", "--ffk", "10"});
  LONGS_EQUAL(0, run.status);
  const nlohmann::json stats = last_line_json(run.out);
  CHECK_TRUE(stats["K"].is_null());
  DOUBLES_EQUAL(1.0, stats["p_stick"].get<double>(), 0.0);
}
