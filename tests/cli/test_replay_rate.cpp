// replay's --rate is the recording's sample rate, as on every command that reads a recording
// (docs/RECORDINGS.md); the pace is --pace max|realtime, and --rate max / --rate realtime, the
// spelling before --pace, still pace the stream.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
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
using stickslip::test::write_text;

namespace {

constexpr int kSamples = 2000;

// A floor signal that makes the seat stick and slip with --ffk 40: 0.9 m/s^2 at 2.3 Hz over a
// 31 Hz ripple.
double floor_m_per_s2(int n) {
  const double t = n / 1000.0;
  return 0.9 * std::sin(2.0 * 3.14159265358979 * 2.3 * t) +
         0.2 * std::sin(2.0 * 3.14159265358979 * 31.0 * t);
}

void check_one_line(const CliRun& run, int status, const std::string& message) {
  LONGS_EQUAL(status, run.status);
  LONGS_EQUAL(1, split_lines(run.err).size());
  STRCMP_CONTAINS(message.c_str(), run.err.c_str());
}

}  // namespace

TEST_GROUP(ReplayRate) {
  TempDir dir;
  std::string timed, untimed;
  void setup() override {
    CHECK_TRUE(dir.ok());
    timed = dir.file("timed.csv");
    untimed = dir.file("untimed.txt");
    std::string with_t = "t,a_u\n", without_t = "AccZ\n";
    char row[80];
    for (int n = 0; n < kSamples; ++n) {
      // n / 1000.0 is the time the --rate path makes for sample n: the same double.
      std::snprintf(row, sizeof row, "%.17g,%.17g\n", n / 1000.0, floor_m_per_s2(n));
      with_t += row;
      std::snprintf(row, sizeof row, "%.17g\n", floor_m_per_s2(n));
      without_t += row;
    }
    write_text(timed, with_t);
    write_text(untimed, without_t);
  }
  CliRun replay(const std::string& input, const std::string& output,
                std::vector<std::string> extra) {
    std::vector<std::string> arguments = {"replay",     "--input", input,      "--output",
                                          output,       "--bus",   "loopback", "--model",
                                          "stick-slip", "--ffk",   "40"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_stickslip(arguments);
  }
};

// The file without a time column at --rate 1000 is the timed file: the node's trace is the same
// bytes, and the statistics the same.
TEST(ReplayRate, RateGivesATextFileWithoutTimesItsSampleTimes) {
  const CliRun reference = replay(timed, dir.file("a.csv"), {});
  LONGS_EQUAL_TEXT(0, reference.status, reference.err.c_str());
  const CliRun rated = replay(untimed, dir.file("b.csv"), {"--signal", "AccZ", "--rate", "1000"});
  LONGS_EQUAL_TEXT(0, rated.status, rated.err.c_str());
  STRCMP_EQUAL("", rated.err.c_str());
  const std::string trace = read_text(dir.file("a.csv"));
  LONGS_EQUAL(kSamples + 1, split_lines(trace).size());
  CHECK_TRUE(trace == read_text(dir.file("b.csv")));
  // The statistics but the timing and the file names.
  auto figures = [](const CliRun& run) {
    nlohmann::json stats = nlohmann::json::parse(split_lines(run.out).back());
    for (const char* key : {"ns_per_sample", "input", "output"}) stats.erase(key);
    return stats.dump();
  };
  STRCMP_EQUAL(figures(reference).c_str(), figures(rated).c_str());
  // Without --rate the time column is missing: refused, naming both ways out.
  check_one_line(replay(untimed, dir.file("c.csv"), {"--signal", "AccZ"}), 1,
                 "no time column (columns: AccZ); give --time NAME or --rate HZ");
}

// --pace realtime and the old --rate realtime both pace the stream (and say so); a rate that is
// neither a number nor a pace, and two paces that disagree, are refused.
TEST(ReplayRate, PaceIsPaceAndRateMaxOrRealtimeStillMeanIt) {
  for (const char* option : {"--pace", "--rate"}) {
    const CliRun run = replay(timed, dir.file("p.csv"), {option, "realtime"});
    LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
    STRCMP_CONTAINS(("replay: streaming " + timed + " over loopback in real time").c_str(),
                    run.err.c_str());
    const CliRun fast = replay(timed, dir.file("f.csv"), {option, "max"});
    LONGS_EQUAL_TEXT(0, fast.status, fast.err.c_str());
    STRCMP_EQUAL("", fast.err.c_str());
  }
  check_one_line(replay(timed, dir.file("x.csv"), {"--rate", "fast"}), 2,
                 "--rate: 'fast' is neither a sample rate > 0 (Hz) nor max or realtime");
  check_one_line(replay(timed, dir.file("x.csv"), {"--rate", "-5"}), 2,
                 "--rate: '-5' is neither a sample rate > 0 (Hz)");
  check_one_line(replay(timed, dir.file("x.csv"), {"--rate", "realtime", "--pace", "max"}), 2,
                 "--rate realtime and --pace max: give one pace");
  check_one_line(replay(timed, dir.file("x.csv"), {"--pace", "slow"}), 2,
                 "--pace: unknown pace 'slow' (expected max or realtime)");
}
