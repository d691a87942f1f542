// A CAN log of two buses on the command line (docs/RECORDINGS.md, "Flags"): --channel picks the
// bus whose frames are decoded, a message on two buses is refused until one is picked, and
// inspect lists the channels and counts the frames too short for a signal.
#include <cstdio>
#include <string>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::split_lines;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

const std::string kDbc = std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc";

std::string hex(int byte) {
  char text[4];
  std::snprintf(text, sizeof text, "%02X", byte);
  return text;
}

// SeatInput (0x100) at 1 kHz on can0 (a_u raw n mod 100) and can1 (100 + n mod 100); the first
// `short_frames` of can0's carry 4 bytes, too few for a_u (bytes 4-5).
std::string two_bus_log(int short_frames = 0) {
  std::string text;
  char line[96];
  for (int n = 0; n < 400; ++n) {
    std::snprintf(line, sizeof line, "(1700000000.%06d) can0 100#00000000%s\n", n * 1000,
                  n < short_frames ? "" : (hex(n % 100) + "000000").c_str());
    text += line;
    std::snprintf(line, sizeof line, "(1700000000.%06d) can1 100#00000000%s000000\n",
                  n * 1000 + 300, hex(100 + n % 100).c_str());
    text += line;
  }
  return text;
}

}  // namespace

TEST_GROUP(CanLogChannelOption) {
  TempDir dir;
  std::string log;
  void setup() override {
    CHECK_TRUE(dir.ok());
    log = dir.file("bus.log");
    write_text(log, two_bus_log());
  }
  CliRun simulate(const std::vector<std::string>& extra) {
    std::vector<std::string> arguments{
        "simulate",         "--input",       log,       "--dbc",      kDbc,
        "--signal",         "SeatInput.a_u", "--model", "stick-slip", "--output",
        dir.file("out.csv")};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_stickslip(arguments);
  }
};

TEST(CanLogChannelOption, SimulateDecodesTheBusThatChannelPicks) {
  const CliRun run = simulate({"--channel", "can1"});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  const auto table = stickslip::test::read_table(dir.file("out.csv"));
  LONGS_EQUAL(400, table.rows.size());
}

TEST(CanLogChannelOption, AMessageOnTwoBusesWithoutChannelIsOneLineAndNoOutput) {
  const CliRun run = simulate({});
  LONGS_EQUAL(2, run.status);
  STRCMP_EQUAL(("stickslip: " + log +
                ": message 'SeatInput' is on channels can0, can1; pick one bus with --channel "
                "NAME\n")
                   .c_str(),
               run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
}

TEST(CanLogChannelOption, AChannelTheLogDoesNotHaveIsRefusedNamingTheChannelsPresent) {
  const CliRun run = simulate({"--channel", "vcan0"});
  LONGS_EQUAL(2, run.status);
  STRCMP_EQUAL(("stickslip: --channel vcan0: " + log +
                " has no frame on that channel (its channels: can0, can1)\n")
                   .c_str(),
               run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.csv")));
}

TEST(CanLogChannelOption, InspectListsTheChannelsAndSuggestsOne) {
  const CliRun ids = run_stickslip({"inspect", log});
  LONGS_EQUAL_TEXT(0, ids.status, ids.err.c_str());
  STRCMP_CONTAINS("channels: can0 (400 frames), can1 (400 frames) (pick one with --channel NAME)",
                  ids.out.c_str());
  // The rate from the mean step, which the epoch clock's rounding does not bias (its median
  // would give 1000.07 Hz).
  STRCMP_CONTAINS("  can0 100: 400 frames, 1000 Hz\n", ids.out.c_str());
  STRCMP_CONTAINS("  can1 100: 400 frames, 1000 Hz\n", ids.out.c_str());
  const CliRun signals = run_stickslip({"inspect", log, "--dbc", kDbc});
  LONGS_EQUAL_TEXT(0, signals.status, signals.err.c_str());
  STRCMP_CONTAINS("SeatInput.a_u on can1 [m/s^2]", signals.out.c_str());
  const std::string suggested = split_lines(signals.out).back();
  STRCMP_CONTAINS(" --channel can0 --signal SeatInput.a_u", suggested.c_str());
}

TEST(CanLogChannelOption, InspectCountsTheFramesTooShortForASignal) {
  write_text(log, two_bus_log(7));
  const CliRun run = run_stickslip({"inspect", log, "--dbc", kDbc, "--channel", "can0"});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  STRCMP_CONTAINS(
      "  SeatInput.a_u: 7 frames of the message too short for the signal (not decoded)\n",
      run.out.c_str());
  const CliRun whole = run_stickslip({"inspect", log, "--dbc", kDbc, "--channel", "can1"});
  CHECK(whole.out.find("too short") == std::string::npos);
}

TEST(CanLogChannelOption, InspectWithChannelOnATextRecordingNamesTheOption) {
  const std::string text = dir.file("floor.csv");
  write_text(text, "t,a_u\n0,0.1\n0.001,0.2\n0.002,0.3\n");
  const CliRun run = run_stickslip({"inspect", text, "--channel", "can0"});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS(("stickslip: --channel can0: " + text + ": not a CAN log").c_str(),
                  run.err.c_str());
  CHECK(run.out.empty());
}
