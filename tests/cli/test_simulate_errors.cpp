#include <string>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

// Bad input: non-zero status, exactly one line on stderr naming the file (and line) and the
// problem, nothing on stdout, and neither OUT.csv nor STATS.json (nor a temporary) left behind.
TEST_GROUP(SimulateErrors) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }

  std::string write_input(const std::string& text) {
    stickslip::test::write_text(dir.file("in.csv"), text);
    return dir.file("in.csv");
  }

  void expect_refused(const std::vector<std::string>& arguments, const std::string& message,
                      int status = 1) {
    std::vector<std::string> all{"simulate", "--output", dir.file("out.csv"), "--stats",
                                 dir.file("stats.json")};
    all.insert(all.end(), arguments.begin(), arguments.end());
    const CliRun run = run_stickslip(all);
    LONGS_EQUAL(status, run.status);
    STRCMP_EQUAL(("stickslip: " + message + "\n").c_str(), run.err.c_str());
    STRCMP_EQUAL("", run.out.c_str());
    CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
    CHECK_FALSE(stickslip::test::exists(dir.file("stats.json")));
    for (const std::string& name : dir.entries()) STRCMP_EQUAL("in.csv", name.c_str());
  }
  void expect_refused_file(const std::string& text, const std::string& message) {
    const std::string in = write_input(text);
    expect_refused({"--input", in, "--model", "stick-slip", "--ffk", "45"}, in + message);
  }
};

TEST(SimulateErrors, MissingFile) {
  const std::string in = dir.file("in.csv");
  expect_refused({"--input", in, "--model", "signum"},
                 in + ": cannot open: No such file or directory");
}

// A directory opens as a stream; its first read would throw a message naming no file.
TEST(SimulateErrors, ADirectoryAsTheRecordingOrItsDbcIsNamed) {
  TempDir other;
  CHECK_TRUE(other.ok());
  const std::string folder = other.file(".");
  expect_refused({"--input", folder, "--signal", "a_u", "--model", "signum"},
                 folder + ": cannot read: it is a directory");
  const std::string in = write_input("t,a_u\n0,1\n0.001,2\n");
  expect_refused({"--input", in, "--dbc", folder, "--signal", "M.S", "--model", "signum"},
                 folder + ": cannot read: it is a directory");
}

// --dt in ms by mistake: refused before a grid of billions of samples is allocated.
TEST(SimulateErrors, AStepThatWouldMakeBillionsOfSamplesIsRefusedUpFront) {
  std::string text = "t [s],AccZ [g]\n";
  for (int n = 0; n < 2000; ++n) text += std::to_string(n * 0.002) + ",1.0\n";
  const std::string in = write_input(text);
  expect_refused({"--input", in, "--signal", "AccZ", "--dt", "1e-9", "--model", "signum"},
                 "--dt 1e-09: 4e+09 samples from the 3.998 s of " + in +
                     ", more than the 1e+09 a recording may have (--dt is in seconds)",
                 2);
}

TEST(SimulateErrors, EmptyFile) {
  expect_refused_file("", ":1: the file is empty; expected a header line naming the columns");
}

TEST(SimulateErrors, MissingColumn) {
  expect_refused_file("t,a_x\n0,1\n0.001,2\n",
                      ":1: missing column 'a_u' (the header names: t,a_x)");
  expect_refused_file("time,a_u\n0,1\n0.001,2\n",
                      ":1: missing column 't' (the header names: time,a_u)");
}

TEST(SimulateErrors, NonNumericCell) {
  expect_refused_file("t,a_u\n0,1\n0.001,2\n0.002,abc\n",
                      ":4: column 'a_u': 'abc' is not a number");
  expect_refused_file("t,a_u\n0,1\nx,2\n", ":3: column 't': 'x' is not a number");
}

TEST(SimulateErrors, NanOrInfiniteCell) {
  expect_refused_file("t,a_u\n0,1\n0.001,NaN\n", ":3: column 'a_u': 'NaN' is not a finite number");
  expect_refused_file("t,a_u\n0,1\n0.001,inf\n", ":3: column 'a_u': 'inf' is not a finite number");
  expect_refused_file("t,a_u\n0,1\n0.001,1e400\n",
                      ":3: column 'a_u': '1e400' is out of the range of a double");
}

TEST(SimulateErrors, NonUniformTime) {
  expect_refused_file("t,a_u\n0,1\n0.001,1\n0.002,1\n0.0035,1\n",
                      ":5: column 't': t is not uniform: the step 0.0015 s differs from the first "
                      "step 0.001 s by more than 1e-06 of it");
  expect_refused_file("t,a_u\n0,1\n0.001,1\n0.001,1\n",
                      ":4: column 't': t must increase, got 0.001 after 0.001");
}

TEST(SimulateErrors, FewerThanTwoSamples) {
  expect_refused_file("t,a_u\n0,1\n", ":2: only 1 sample after the header; at least 2 are needed");
  expect_refused_file("t,a_u\n", ":1: no samples after the header; at least 2 are needed");
}

TEST(SimulateErrors, ValuesBeyondFloatForAFloatRun) {
  const std::string in = write_input("t,a_u\n0,1\n0.001,1e39\n");
  expect_refused(
      {"--input", in, "--model", "signum", "--scalar", "float"},
      in + ": a_u = 1e+39 at t = 0.001 s is beyond the range of a float (--scalar float)");
}

TEST(SimulateErrors, RaggedRow) {
  expect_refused_file("t,a_u\n0,1\n0.001\n",
                      ":3: expected 2 fields like the header (t,a_u), found 1");
}

TEST(SimulateErrors, UnknownFlagModelIntegratorScalarOrSmoothing) {
  const std::string in = write_input("t,a_u\n0,1\n0.001,2\n");
  expect_refused({"--input", in, "--model", "signum", "--bogus", "1"},
                 "simulate: unknown option '--bogus'; see stickslip simulate --help", 2);
  expect_refused({"--input", in, "--model", "coulomb"},
                 "--model: unknown model 'coulomb' (expected linear, signum, smooth, stick-slip or "
                 "stribeck)",
                 2);
  expect_refused({"--input", in, "--model", "signum", "--integrator", "rk45"},
                 "--integrator: unknown integrator 'rk45' (expected euler, symplectic, rk4, exact "
                 "or reference; did you mean rk4?)",
                 2);
  expect_refused({"--input", in, "--model", "signum", "--scalar", "half"},
                 "--scalar: unknown scalar 'half' (expected double, float, fixed or fixed32)", 2);
  expect_refused({"--input", in, "--model", "smooth", "--smoothing", "sigmoid"},
                 "--smoothing: unknown form 'sigmoid' (expected atan, tanh, erf or rational)", 2);
  expect_refused({"--input", in}, "--model is required (or give a --scene)", 2);
  expect_refused({"--input", in, "--model", "signum", "--mass", "heavy"},
                 "Could not convert: --mass = heavy", 2);
  expect_refused({"--input", in, "--model", "signum", "--x0", "nan"},
                 "--x0: must be a finite number, got nan", 2);
}

// Values out of range on the command line are command-line errors (status 2), not bad data.
TEST(SimulateErrors, InvalidParametersNameTheOptionAndTheLimit) {
  const std::string in = write_input("t,a_u\n0,1\n0.001,2\n0.002,0\n");
  expect_refused({"--input", in, "--model", "signum", "--mass", "-1"},
                 "--mass: mass_kg: must be >= 1e-06 and <= 1e+09 kg, got -1", 2);
  expect_refused({"--input", in, "--model", "stick-slip", "--ffk", "45", "--ffs", "30"},
                 "--ffs: static_friction_n: F_fs = 30 N is below the kinetic friction F_fk = 45 N; "
                 "static friction must be >= kinetic",
                 2);
  expect_refused({"--input", in, "--model", "signum", "--damping", "-5"},
                 "--damping: damping_ns_per_m: must be >= 0 and <= 1e+09 N s/m, got -5", 2);
  expect_refused({"--input", in, "--model", "stick-slip", "--ffk", "-1"},
                 "--ffk: kinetic_friction_n: must be >= 0 and <= 1e+09 N, got -1", 2);
}

TEST(SimulateErrors, AStepTheModelCannotTakeNamesTheFile) {
  const std::string in = write_input("t,a_u\n0,1\n0.5,2\n1.0,0\n");  // dt = 0.5 s
  const std::vector<std::string> arguments{
      "simulate", "--input",    in,      "--output", dir.file("out.csv"),
      "--model",  "stick-slip", "--ffk", "45"};
  const CliRun run = run_stickslip(arguments);
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS(("stickslip: " + in +
                   ": the time step of the file (dt = 0.5 s) does not suit this "
                   "model: dt_s: ")
                      .c_str(),
                  run.err.c_str());
  LONGS_EQUAL(1, stickslip::test::split_lines(run.err).size());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
  LONGS_EQUAL(1, dir.entries().size());
}

// The model's step given by --dt is the option's value, a command-line error, not the file's.
TEST(SimulateErrors, ADtOptionTheModelCannotTakeIsNamedAsTheOption) {
  std::string text = "t,a_u\n";
  for (int n = 0; n <= 40; ++n) text += std::to_string(n * 0.5) + ",0.5\n";
  const std::string in = write_input(text);
  const CliRun run = run_stickslip({"simulate", "--input", in, "--output", dir.file("out.csv"),
                                    "--dt", "2", "--model", "stick-slip", "--ffk", "45"});
  LONGS_EQUAL(2, run.status);
  STRCMP_CONTAINS("stickslip: --dt 2: the model's step does not suit this model: dt_s: ",
                  run.err.c_str());
  CHECK(run.err.find("the time step of the file") == std::string::npos);
  LONGS_EQUAL(1, stickslip::test::split_lines(run.err).size());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
}

TEST(SimulateErrors, UnwritableOutputAndClashingNames) {
  const std::string in = write_input("t,a_u\n0,1\n0.001,2\n");
  const CliRun run = run_stickslip(
      {"simulate", "--input", in, "--output", dir.file("no/out.csv"), "--model", "signum"});
  LONGS_EQUAL(1, run.status);
  STRCMP_EQUAL(("stickslip: " + dir.file("no/out.csv") +
                ": cannot create the output file: No such file or directory\n")
                   .c_str(),
               run.err.c_str());
  const CliRun same = run_stickslip({"simulate", "--input", in, "--output", dir.file("x.csv"),
                                     "--stats", dir.file("x.csv"), "--model", "signum"});
  LONGS_EQUAL(2, same.status);
  STRCMP_CONTAINS(
      ("--stats " + dir.file("x.csv") + " and --output " + dir.file("x.csv") + " are the same file")
          .c_str(),
      same.err.c_str());
  LONGS_EQUAL(1, dir.entries().size());
}

TEST(SimulateErrors, AFailedRunLeavesAnEarlierOutputUntouched) {
  stickslip::test::write_text(dir.file("out.csv"), "previous\n");
  const std::string in = write_input("t,a_u\n0,1\n0.001,oops\n");
  const CliRun run = run_stickslip(
      {"simulate", "--input", in, "--output", dir.file("out.csv"), "--model", "signum"});
  LONGS_EQUAL(1, run.status);
  STRCMP_EQUAL("previous\n", stickslip::test::read_text(dir.file("out.csv")).c_str());
  LONGS_EQUAL(2, dir.entries().size());
}
