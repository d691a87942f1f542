#include <string>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

TEST_GROUP(DemoCommand) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

TEST(DemoCommand, TabulatesTheModelsAndNamesTheModelTheSceneNeeds) {
  const std::string out_dir = dir.file("demo");
  const CliRun run = run_stickslip({"demo", "--duration", "20", "--out-dir", out_dir});
  LONGS_EQUAL(0, run.status);
  STRCMP_EQUAL("", run.err.c_str());
  STRCMP_CONTAINS("model       integrator   a0u [m/s^2]       K    T_ax       p  ns/sample",
                  run.out.c_str());
  STRCMP_CONTAINS("\nsignum      euler             0.3500   1.309", run.out.c_str());
  STRCMP_CONTAINS("\nsignum      exact             0.3500   1.309", run.out.c_str());
  STRCMP_CONTAINS("\nstick-slip  exact             0.3500   1.309", run.out.c_str());
  // K = 4*45/(pi*sqrt(2)*88.4*0.35) = 1.309 > 0.75.
  STRCMP_CONTAINS("K = 1.31 > 0.75: stick-slip required", run.out.c_str());
  STRCMP_CONTAINS("signum (ode1) gives T_ax = ", run.out.c_str());
  // The recording replayed over the default bus to the ECU node, with its fault counters.
  STRCMP_CONTAINS("\nreplay over ", run.out.c_str());
  STRCMP_CONTAINS("20001 frames sent, 20001 samples", run.out.c_str());
  STRCMP_CONTAINS("\nfaults 0: frames 20001 accepted 20001 ", run.out.c_str());
  STRCMP_CONTAINS("simulate on the quantised samples gives the same output, bit for bit",
                  run.out.c_str());
  for (const char* name : {"lorry.csv", "signum-euler.csv", "signum-euler.json", "signum-exact.csv",
                           "signum-exact.json", "stick-slip-exact.csv", "stick-slip-exact.json",
                           "stick-slip-replay.csv", "stick-slip-quantised.csv"}) {
    CHECK_TRUE(stickslip::test::exists(out_dir + "/" + name));
  }
}

TEST(DemoCommand, LowFrictionSaysSignumSuffices) {
  const CliRun run =
      run_stickslip({"demo", "--duration", "5", "--ffk", "5", "--out-dir", dir.file("d")});
  LONGS_EQUAL(0, run.status);
  STRCMP_CONTAINS("K = 0.15 < 0.4: signum suffices", run.out.c_str());
}

TEST(DemoCommand, NoClobberKeepsAnEarlierFileAndWritesNothing) {
  const std::string out_dir = dir.file("kept");
  const CliRun made = run_stickslip({"demo", "--duration", "2", "--out-dir", out_dir});
  LONGS_EQUAL(0, made.status);
  stickslip::test::write_text(out_dir + "/stick-slip-exact.json", "the user's own\n");
  const std::string recording = stickslip::test::read_text(out_dir + "/lorry.csv");
  const CliRun kept =
      run_stickslip({"demo", "--duration", "3", "--out-dir", out_dir, "--no-clobber"});
  LONGS_EQUAL(1, kept.status);
  STRCMP_EQUAL("", kept.out.c_str());
  STRCMP_EQUAL(("stickslip: --out-dir " + out_dir +
                ": lorry.csv exists, and --no-clobber keeps it (nothing written)\n")
                   .c_str(),
               kept.err.c_str());
  STRCMP_EQUAL("the user's own\n",
               stickslip::test::read_text(out_dir + "/stick-slip-exact.json").c_str());
  CHECK_TRUE(recording == stickslip::test::read_text(out_dir + "/lorry.csv"));
  // A folder of its own: the demo runs, as without the flag.
  LONGS_EQUAL(
      0, run_stickslip({"demo", "--duration", "2", "--out-dir", dir.file("fresh"), "--no-clobber"})
             .status);
}

TEST(DemoCommand, BadOptionsAreRefused) {
  const CliRun run = run_stickslip({"demo", "--dt", "0.1", "--out-dir", dir.file("d")});
  LONGS_EQUAL(2, run.status);
  STRCMP_CONTAINS("stickslip: --dt: lorry needs 0.5/dt above 20 Hz", run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("d")));
  LONGS_EQUAL(2, run_stickslip({"demo", "--ffk", "-3", "--out-dir", dir.file("d")}).status);
}

TEST_GROUP(Cli){};

TEST(Cli, HelpListsTheSubcommandsAndTheirOptions) {
  const CliRun help = run_stickslip({"--help"});
  LONGS_EQUAL(0, help.status);
  STRCMP_CONTAINS("generate", help.out.c_str());
  STRCMP_CONTAINS("simulate", help.out.c_str());
  STRCMP_CONTAINS("demo", help.out.c_str());
  const CliRun simulate_help = run_stickslip({"simulate", "--help"});
  LONGS_EQUAL(0, simulate_help.status);
  for (const char* option : {"--input", "--output", "--stats", "--model", "--mass", "--stiffness",
                             "--damping", "--ffk", "--ffs", "--stribeck-velocity", "--smoothing",
                             "--smoothing-c", "--integrator", "--scalar", "--x0", "--v0"}) {
    STRCMP_CONTAINS(option, simulate_help.out.c_str());
  }
}

TEST(Cli, UsageErrorsAreOneLineWithStatusTwo) {
  const CliRun none = run_stickslip({});
  LONGS_EQUAL(2, none.status);
  STRCMP_EQUAL(
      "stickslip: a subcommand is required: generate, simulate, demo, replay, ecu, record, play, "
      "sweep, merge, psd, harmonic-balance, advise, inspect, fit, closed-loop, plant or controller "
      "(stickslip --help describes them; stickslip SUBCOMMAND --help its options)\n",
      none.err.c_str());
  const CliRun unknown = run_stickslip({"simulat"});
  LONGS_EQUAL(2, unknown.status);
  STRCMP_EQUAL(
      "stickslip: unknown subcommand 'simulat' (did you mean simulate?); expected generate, "
      "simulate, demo, replay, ecu, record, play, sweep, merge, psd, harmonic-balance, advise, "
      "inspect, fit, closed-loop, plant or controller (see stickslip --help)\n",
      unknown.err.c_str());
  const CliRun flag = run_stickslip({"--verbose"});
  LONGS_EQUAL(2, flag.status);
  LONGS_EQUAL(1, stickslip::test::split_lines(flag.err).size());
}
