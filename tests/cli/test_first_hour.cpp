// What a newcomer runs into in the first hour, each reproduced from the user's command: an output
// that is the input, an existing output, a mistyped option or bus, a flag blamed that was never
// given, a bound printed as 309 digits, options silently combined or ignored, a missing version.
#include <unistd.h>

#include <string>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::read_text;
using stickslip::test::run_stickslip;
using stickslip::test::split_lines;
using stickslip::test::TempDir;

namespace {

const char* const kRecording = "t,a_u\n0,1\n0.001,2\n0.002,0\n0.003,-1\n";

void check_one_line(const CliRun& run, int status, const std::string& message) {
  LONGS_EQUAL(status, run.status);
  LONGS_EQUAL(1, split_lines(run.err).size());
  STRCMP_EQUAL(("stickslip: " + message + "\n").c_str(), run.err.c_str());
}

}  // namespace

TEST_GROUP(FirstHour) {
  TempDir dir;
  std::string in;
  void setup() override {
    CHECK_TRUE(dir.ok());
    in = dir.file("l.csv");
    stickslip::test::write_text(in, kRecording);
  }
};

TEST(FirstHour, SimulateOutputThatIsTheInputIsRefusedAndTheRecordingKept) {
  const CliRun run =
      run_stickslip({"simulate", "--input", in, "--output", in, "--model", "signum"});
  check_one_line(
      run, 2,
      "--output " + in + " is the file --input " + in + " reads; write the result to another file");
  STRCMP_EQUAL(kRecording, read_text(in).c_str());
}

TEST(FirstHour, SweepOutputThatIsTheInputIsRefusedAndTheRecordingKept) {
  const CliRun run =
      run_stickslip({"sweep", "--input", in, "--damping", "500", "--k", "1", "--output", in});
  LONGS_EQUAL(2, run.status);
  STRCMP_CONTAINS("is the file --input", run.err.c_str());
  STRCMP_EQUAL(kRecording, read_text(in).c_str());
}

// The vehicle's DBC is read as the recording is: an output or stats file naming it would replace
// the user's database with a trace.
TEST(FirstHour, OutputOrStatsThatIsTheDbcIsRefusedAndTheDbcKept) {
  const std::string dbc = dir.file("vehicle.dbc");
  const std::string text = "VERSION \"\"\n";
  stickslip::test::write_text(dbc, text);
  const std::string out = dir.file("o.csv");
  for (const char* option : {"--output", "--stats"}) {
    const bool stats = std::string(option) == "--stats";
    const CliRun run =
        run_stickslip({"simulate", "--input", in, "--dbc", dbc, "--output", stats ? out : dbc,
                       "--stats", stats ? dbc : dir.file("s.json"), "--model", "signum"});
    check_one_line(run, 2,
                   std::string(option) + " " + dbc + " is the file --dbc " + dbc +
                       " reads; write the result to another file");
    STRCMP_EQUAL(text.c_str(), read_text(dbc).c_str());
  }
}

TEST(FirstHour, OutputThatResolvesToTheInputThroughALinkIsRefused) {
  const std::string link = dir.file("link.csv");
  CHECK_EQUAL(0, ::symlink(in.c_str(), link.c_str()));
  const CliRun run =
      run_stickslip({"simulate", "--input", in, "--output", link, "--model", "signum"});
  LONGS_EQUAL(2, run.status);
  STRCMP_CONTAINS(("--output " + link + " is the file --input " + in).c_str(), run.err.c_str());
  const CliRun stats = run_stickslip({"simulate", "--input", in, "--output", dir.file("o.csv"),
                                      "--stats", dir.file("./o.csv"), "--model", "signum"});
  LONGS_EQUAL(2, stats.status);
  STRCMP_CONTAINS("are the same file", stats.err.c_str());
  STRCMP_EQUAL(kRecording, read_text(in).c_str());
}

TEST(FirstHour, NoClobberRefusesAnExistingOutputAndKeepsIt) {
  const std::string out = dir.file("out.csv");
  stickslip::test::write_text(out, "keep me\n");
  const CliRun run = run_stickslip(
      {"simulate", "--input", in, "--output", out, "--model", "signum", "--no-clobber"});
  check_one_line(run, 1, "--output " + out + ": exists, and --no-clobber keeps it");
  STRCMP_EQUAL("keep me\n", read_text(out).c_str());
  const CliRun generate = run_stickslip({"generate", "--kind", "lorry", "--rms", "1", "--duration",
                                         "1", "--dt", "0.01", "--output", out, "--no-clobber"});
  LONGS_EQUAL(1, generate.status);
  STRCMP_EQUAL("keep me\n", read_text(out).c_str());
  // Without it, a complete run replaces the file (atomically, as before).
  LONGS_EQUAL(
      0, run_stickslip({"simulate", "--input", in, "--output", out, "--model", "signum"}).status);
  STRCMP_CONTAINS("t,a_u,x_r", read_text(out).c_str());
}

TEST(FirstHour, MistypedOptionIsNamedWithTheClosestValidOne) {
  check_one_line(run_stickslip({"generate", "--kind", "lorry", "--rms", "1", "--duration", "1",
                                "--dt", "0.01", "--ouput", dir.file("g.csv")}),
                 2,
                 "generate: unknown option '--ouput' (did you mean --output?); see stickslip "
                 "generate --help");
  check_one_line(run_stickslip({"simulate", "--input", in, "--output", dir.file("o.csv"), "--model",
                                "signum", "--fkk", "45"}),
                 2,
                 "simulate: unknown option '--fkk' (did you mean --ffk?); see stickslip simulate "
                 "--help");
  CHECK_FALSE(stickslip::test::exists(dir.file("g.csv")));
}

TEST(FirstHour, MistypedBusIsNamedWithLoopback) {
  check_one_line(run_stickslip({"replay", "--input", in, "--output", dir.file("r.csv"), "--model",
                                "stick-slip", "--bus", "loopbak"}),
                 2,
                 "--bus loopbak: no such bus (did you mean loopback? otherwise a CAN interface "
                 "of this machine, such as vcan0)");
}

TEST(FirstHour, FixedPointWithoutIntegratorBlamesTheModelsDefaultNotTheFlag) {
  check_one_line(run_stickslip({"simulate", "--input", in, "--output", dir.file("o.csv"), "--model",
                                "smooth", "--smoothing", "rational", "--scalar", "fixed"}),
                 2,
                 "--scalar fixed: the default integrator of --model smooth is rk4, which fixed "
                 "point does not offer; give --integrator exact, symplectic or euler");
}

TEST(FirstHour, RepetitionsZeroStatesTheBoundPlainly) {
  check_one_line(run_stickslip({"simulate", "--input", in, "--output", dir.file("o.csv"), "--model",
                                "signum", "--repetitions", "0"}),
                 2, "--repetitions: must be a whole number >= 1, got '0'");
}

// Every checked number option: the rule and the value typed, never the largest double's 309
// digits as the bound.
TEST(FirstHour, EveryNumberBoundIsStatedPlainly) {
  const struct {
    std::vector<std::string> arguments;
    const char* message;
  } cases[] = {
      {{"ecu", "--timeout", "-1"}, "--timeout: must be a finite number >= 0, got -1"},
      {{"ecu", "--timeout", "inf"}, "--timeout: must be a finite number >= 0, got inf"},
      {{"ecu", "--output-every", "0"}, "--output-every: must be a whole number >= 1, got '0'"},
      {{"fit", "--input", in, "--travel-noise", "0"},
       "--travel-noise: must be a finite number > 0, got 0"},
      {{"fit", "--input", in, "--travel-noise", "1e-4m"},
       "--travel-noise: must be a finite number > 0, got 1e-4m"},
      {{"fit", "--input", in, "--max-iterations", "2.5"},
       "--max-iterations: must be a whole number >= 1, got '2.5'"},
      {{"simulate", "--input", in, "--rate", "0"}, "--rate: must be a finite number > 0, got 0"},
      {{"psd", "--input", in, "--dt", "nan"}, "--dt: must be a finite number > 0, got nan"},
  };
  for (const auto& c : cases) check_one_line(run_stickslip(c.arguments), 2, c.message);
}

TEST(FirstHour, VersionPrintsTheVersionAndTheCommit) {
  const CliRun run = run_stickslip({"--version"});
  LONGS_EQUAL(0, run.status);
  STRCMP_EQUAL("", run.err.c_str());
  CHECK(run.out.rfind("stickslip ", 0) == 0);
  STRCMP_CONTAINS(" (git ", run.out.c_str());
  LONGS_EQUAL(1, split_lines(run.out).size());
}

TEST(FirstHour, BareStickslipListsTheSubcommands) {
  const CliRun run = run_stickslip({});
  LONGS_EQUAL(2, run.status);
  LONGS_EQUAL(1, split_lines(run.err).size());
  for (const char* name : {"generate", "simulate", "demo", "sweep", "advise"})
    STRCMP_CONTAINS(name, run.err.c_str());
}

TEST(FirstHour, ValuesOutOfRangeAreCommandLineErrors) {
  const std::string out = dir.file("o.csv");
  LONGS_EQUAL(2, run_stickslip({"simulate", "--input", in, "--output", out, "--model", "signum",
                                "--mass", "-1"})
                     .status);
  LONGS_EQUAL(2, run_stickslip({"simulate", "--input", in, "--output", out, "--model", "stick-slip",
                                "--ffs", "30", "--ffk", "45"})
                     .status);
  LONGS_EQUAL(2, run_stickslip({"simulate", "--input", in, "--output", out, "--model", "signum",
                                "--mass", "abc"})
                     .status);
  CHECK_FALSE(stickslip::test::exists(out));
}

TEST(FirstHour, EcuOnTheLoopbackBusIsRefusedInsteadOfWaitingForever) {
  const CliRun run =
      run_stickslip({"ecu", "--bus", "loopback", "--frames", "10", "--model", "stick-slip"});
  LONGS_EQUAL(2, run.status);
  LONGS_EQUAL(1, split_lines(run.err).size());
  STRCMP_CONTAINS("--bus loopback: ecu would wait forever", run.err.c_str());
  STRCMP_CONTAINS("replay --bus loopback", run.err.c_str());
}

TEST(FirstHour, KAndKRangeTogetherAreRefused) {
  check_one_line(run_stickslip({"sweep", "--input", in, "--damping", "500", "--k", "1", "--k-range",
                                "1:2:3", "--output", dir.file("s.csv")}),
                 2, "--k and --k-range: give one of them (both would sweep the union)");
}

TEST(FirstHour, BandCornersForAKindWithoutThemAreRefused) {
  check_one_line(run_stickslip({"generate", "--kind", "lorry", "--rms", "1", "--duration", "1",
                                "--dt", "0.01", "--band-low", "3", "--output", dir.file("g.csv")}),
                 2,
                 "--band-low: only --kind white has corners to set; --kind lorry has its own "
                 "band");
}

TEST(FirstHour, GenerateHelpListsWhiteOnce) {
  const CliRun run = run_stickslip({"generate", "--help"});
  LONGS_EQUAL(0, run.status);
  for (const std::string& line : split_lines(run.out)) {
    if (line.find("--kind") == std::string::npos) continue;
    const std::size_t first = line.find("white");
    CHECK(first != std::string::npos);
    CHECK(line.find("white", first + 1) == std::string::npos ||
          line.find("white", line.find("white", first + 1) + 1) == std::string::npos);
    CHECK(line.find("| white |") == std::string::npos);
  }
}

TEST(FirstHour, OneThreadIsSingular) {
  const CliRun run = run_stickslip({"sweep", "--input", in, "--damping", "500", "--k", "1",
                                    "--threads", "1", "--quiet", "--output", dir.file("s.csv")});
  LONGS_EQUAL(0, run.status);
  STRCMP_CONTAINS(" on 1 thread (", run.out.c_str());
}

TEST(FirstHour, HarmonicBalanceWithoutASolutionWritesNanNotAPerfectMatch) {
  const CliRun run = run_stickslip({"harmonic-balance", "--k-range", "0:1.2:7", "--damping", "504",
                                    "--periods", "30", "--output", dir.file("hb.csv")});
  LONGS_EQUAL(0, run.status);
  std::size_t invalid = 0;
  for (const std::string& line : split_lines(read_text(dir.file("hb.csv")))) {
    const std::vector<std::string> cells = stickslip::test::split_cells(line);
    if (cells.size() != 10 || cells[3] != "0") continue;
    ++invalid;
    STRCMP_EQUAL("nan", cells[4].c_str());  // x_hb_m
    STRCMP_EQUAL("nan", cells[9].c_str());  // rel_error
  }
  CHECK(invalid > 0);
}

TEST(FirstHour, CommandsThatWaitSayWhatTheyWaitFor) {
  const CliRun replay =
      run_stickslip({"replay", "--input", in, "--output", dir.file("r.csv"), "--model",
                     "stick-slip", "--bus", "loopback", "--rate", "realtime"});
  LONGS_EQUAL(0, replay.status);
  STRCMP_CONTAINS(("replay: streaming " + in + " over loopback in real time").c_str(),
                  replay.err.c_str());
  const CliRun play = run_stickslip({"play", "--input", in, "--bus", "loopback"});
  LONGS_EQUAL(0, play.status);
  STRCMP_CONTAINS(("play: sending " + in + " on loopback at 1x real time").c_str(),
                  play.err.c_str());
  // As fast as possible, nothing waits: nothing to say.
  const CliRun fast = run_stickslip({"replay", "--input", in, "--output", dir.file("f.csv"),
                                     "--model", "stick-slip", "--bus", "loopback"});
  LONGS_EQUAL(0, fast.status);
  STRCMP_EQUAL("", fast.err.c_str());
}

TEST(FirstHour, RealtimeReplayWithProgressReportsFramesOnStderr) {
  const std::string three_s = dir.file("three_s.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration", "3",
                                "--dt", "0.001", "--output", three_s})
                     .status);
  const CliRun run =
      run_stickslip({"replay", "--input", three_s, "--output", dir.file("r.csv"), "--model",
                     "stick-slip", "--bus", "loopback", "--rate", "realtime", "--progress"});
  LONGS_EQUAL(0, run.status);
  STRCMP_CONTAINS("/3001 frames (", run.err.c_str());
  CHECK(run.err.find("replay: ") != std::string::npos);
}

TEST(FirstHour, MistypedChoiceIsRefusedWithTheListBeforeAnyFileIsRead) {
  check_one_line(run_stickslip({"simulate", "--input", in, "--output", dir.file("o.csv"), "--scene",
                                dir.file("missing.toml"), "--model", "signun"}),
                 2,
                 "--model: unknown model 'signun' (expected linear, signum, smooth, stick-slip or "
                 "stribeck; did you mean signum?)");
}

TEST(FirstHour, SimulateWithProgressNamesEachStageOnStderrAndIsSilentWithout) {
  const std::string out = dir.file("o.csv");
  const CliRun run = run_stickslip(
      {"simulate", "--input", in, "--output", out, "--model", "signum", "--progress"});
  LONGS_EQUAL(0, run.status);
  const std::vector<std::string> lines = split_lines(run.err);
  LONGS_EQUAL(3, lines.size());
  STRCMP_CONTAINS(("simulate: reading " + in + " (").c_str(), lines[0].c_str());
  STRCMP_CONTAINS("simulate: simulating 4 samples (", lines[1].c_str());
  STRCMP_CONTAINS(("simulate: writing " + out + " (").c_str(), lines[2].c_str());
  // Not a terminal and no --progress: a short run prints nothing on stderr.
  const CliRun quiet =
      run_stickslip({"simulate", "--input", in, "--output", out, "--model", "signum"});
  LONGS_EQUAL(0, quiet.status);
  STRCMP_EQUAL("", quiet.err.c_str());
}
