// --gaps split beyond simulate (docs/RECORDINGS.md, "Gaps"): a recording that lost 0.1 s is two
// parts, and each command treats them as two recordings, never one: psd averages the Welch
// periodograms of each part, weighted by their number (none spans the gap); advise and sweep run
// each part from rest and report the figures over all parts as simulate --gaps split does.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/host/signals/welch.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::column;
using stickslip::test::read_table;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 6000, kGapFrom = 2500, kGapTo = 2600;  // 1 kHz, 0.1 s lost at 2.5 s

double floor_m_per_s2(int n) {
  const double t = n * 0.001;
  return 0.7 * std::sin(2.0 * kPi * 3.1 * t) + 0.3 * std::sin(2.0 * kPi * 17.3 * t + 0.4) +
         0.1 * std::sin(2.0 * kPi * 61.0 * t + 1.1);
}

// The file and its two parts as the test keeps them (the file's own doubles).
struct Gapped {
  std::vector<double> before, after;
};

Gapped write_gapped(const std::string& path) {
  Gapped parts;
  std::string text = "t,a_u\n";
  char row[64];
  for (int n = 0; n < kSamples; ++n) {
    if (n >= kGapFrom && n < kGapTo) continue;
    std::snprintf(row, sizeof row, "%.17g,%.17g\n", n * 0.001, floor_m_per_s2(n));
    text += row;
    (n < kGapFrom ? parts.before : parts.after).push_back(floor_m_per_s2(n));
  }
  write_text(path, text);
  return parts;
}

// 2 s of a 1.5 m/s^2 sine at 2.1 Hz (the seat with F_fk = 60 N slips), 0.1 s lost, then 1 s of
// 0.05 m/s^2: far below F_fk / m = 0.68 m/s^2, so the second part run alone from rest sticks
// throughout (a_x = a_u: T_ax = 1, p = 1 exactly). Carried over the gap, the first part's motion
// would not stop at once: a bridged gap shows in the second part's figures.
void write_slip_then_stick(const std::string& path) {
  std::string text = "t,a_u\n";
  char row[64];
  for (int n = 0; n < 3100; ++n) {
    if (n >= 2000 && n < 2100) continue;
    const double t = n / 1000.0;
    const double a =
        n < 2000 ? 1.5 * std::sin(2.0 * kPi * 2.1 * t) : 0.05 * std::sin(2.0 * kPi * 5 * t);
    std::snprintf(row, sizeof row, "%.17g,%.17g\n", t, a);
    text += row;
  }
  write_text(path, text);
}

nlohmann::json last_json(const CliRun& run) {
  return nlohmann::json::parse(stickslip::test::split_lines(run.out).back());
}

std::string four(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  return text;
}

}  // namespace

TEST_GROUP(GapsSplit) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

// The oracle: each part's Welch PSD (the library's welch_psd on the part alone), averaged with
// the parts' segment counts as weights. A part dropped, or a window across the gap (the parts
// joined), gives other numbers; the test checks that both would.
TEST(GapsSplit, PsdAveragesEachPartsWelchSegmentsAndNoneAcrossTheGap) {
  const std::string input = dir.file("gapped.csv");
  const Gapped parts = write_gapped(input);
  const auto run = run_stickslip({"psd", "--input", input, "--gaps", "split", "--segment", "512",
                                  "--output", dir.file("psd.csv")});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  const auto first = stickslip::host::welch_psd(parts.before, 0.001, 512);
  const auto second = stickslip::host::welch_psd(parts.after, 0.001, 512);
  const std::size_t segments = first.segments + second.segments;
  STRCMP_CONTAINS(("wrote " + dir.file("psd.csv") + ": 257 frequencies, " +
                   std::to_string(segments) + " segments over 2 parts between gaps")
                      .c_str(),
                  run.out.c_str());
  const std::vector<double> psd = column(read_table(dir.file("psd.csv")), 1);
  LONGS_EQUAL(257, psd.size());
  std::vector<double> joined = parts.before;
  joined.insert(joined.end(), parts.after.begin(), parts.after.end());
  const auto bridged = stickslip::host::welch_psd(joined, 0.001, 512);
  double bridged_gap = 0.0, dropped_gap = 0.0;
  for (std::size_t k = 0; k < psd.size(); ++k) {
    const double expected = (first.psd[k] * static_cast<double>(first.segments) +
                             second.psd[k] * static_cast<double>(second.segments)) /
                            static_cast<double>(segments);
    // The same sums in the same order, and 17 digits read back to the same double: equal.
    DOUBLES_EQUAL(expected, psd[k], 0.0);
    bridged_gap = std::max(bridged_gap, std::fabs(bridged.psd[k] - expected) / expected);
    dropped_gap = std::max(dropped_gap, std::fabs(first.psd[k] - expected) / expected);
  }
  CHECK(bridged_gap > 1e-6);
  CHECK(dropped_gap > 1e-6);
  // The stderr line says the file was split.
  CHECK(run.err.find("split into 2 segments") != std::string::npos);
}

// A --segment longer than every part: one line, nothing written.
TEST(GapsSplit, PsdRefusesASegmentLongerThanEveryPart) {
  const std::string input = dir.file("gapped.csv");
  write_gapped(input);
  const auto run = run_stickslip({"psd", "--input", input, "--gaps", "split", "--segment", "4096",
                                  "--output", dir.file("psd.csv")});
  LONGS_EQUAL(2, run.status);
  STRCMP_EQUAL(
      "stickslip: --segment: 4096 samples is longer than every part between the gaps (the "
      "longest has 3400)\n",
      run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("psd.csv")));
}

// advise's reference (stick-slip/exact) per part and over all, against simulate --gaps split of
// the same model: the same figures at advise's 4 digits; the sticking part exactly T_ax = 1, p = 1.
TEST(GapsSplit, AdviseRunsEachPartFromRestAndReportsEachAndTheWhole) {
  const std::string input = dir.file("slip_stick.csv");
  write_slip_then_stick(input);
  const CliRun simulate =
      run_stickslip({"simulate", "--input", input, "--gaps", "split", "--model", "stick-slip",
                     "--ffk", "60", "--output", dir.file("s.csv")});
  LONGS_EQUAL_TEXT(0, simulate.status, simulate.err.c_str());
  const nlohmann::json stats = last_json(simulate);
  const CliRun advise =
      run_stickslip({"advise", "--input", input, "--gaps", "split", "--ffk", "60"});
  LONGS_EQUAL_TEXT(0, advise.status, advise.err.c_str());
  STRCMP_CONTAINS(
      ("stick-slip/exact (reference):             T_ax = " + four(stats["T_ax"].get<double>()))
          .c_str(),
      advise.out.c_str());
  STRCMP_CONTAINS(("part 1 from t = 0 s, 2000 samples, run alone: reference T_ax = " +
                   four(stats["segments"][0]["T_ax"].get<double>()))
                      .c_str(),
                  advise.out.c_str());
  STRCMP_CONTAINS(
      "part 2 from t = 2.1 s, 1000 samples, run alone: reference T_ax = 1.0000, p = 1.000;",
      advise.out.c_str());
  DOUBLES_EQUAL(1.0, stats["segments"][1]["T_ax"].get<double>(), 0.0);
  CHECK(advise.err.find("split into 2 segments") != std::string::npos);
}

// sweep's stick-slip and signum rows against simulate --gaps split at the row's F_fk: the same
// T_ax and p over both parts (RunningStatistics' sums against simulate's weighted parts: equal
// to a few ulps), with the batch and the single-point loops alike.
TEST(GapsSplit, SweepRunsEachPartFromRestAndSumsOverAllParts) {
  const std::string input = dir.file("slip_stick.csv");
  write_slip_then_stick(input);
  for (const char* loop : {"--no-batch", "--quiet"}) {
    const CliRun sweep = run_stickslip({"sweep", "--input", input, "--gaps", "split", "--k", "0.7",
                                        "--damping", "504", loop, "--output", dir.file("k.csv")});
    LONGS_EQUAL_TEXT(0, sweep.status, sweep.err.c_str());
    const std::vector<std::string> lines =
        stickslip::test::split_lines(stickslip::test::read_text(dir.file("k.csv")));
    LONGS_EQUAL(3, lines.size());
    for (std::size_t row = 1; row < lines.size(); ++row) {
      const std::vector<std::string> cells = stickslip::test::split_cells(lines[row]);
      const CliRun simulate =
          run_stickslip({"simulate", "--input", input, "--gaps", "split", "--model", cells[2],
                         "--integrator", cells[3], "--damping", "504", "--ffk", cells[6], "--ffs",
                         cells[7], "--output", dir.file("s.csv")});
      LONGS_EQUAL_TEXT(0, simulate.status, simulate.err.c_str());
      const nlohmann::json stats = last_json(simulate);
      const double t_ax = std::stod(cells[11]), p = std::stod(cells[12]);
      DOUBLES_EQUAL(stats["T_ax"].get<double>(), t_ax, 1e-13 * t_ax);
      DOUBLES_EQUAL(stats["p_stick"].get<double>(), p, 1e-13);
    }
  }
}

// The refusal names the command the user ran, not replay, whose reader play and record share.
TEST(GapsSplit, RecordAndPlayRefuseSplitNamingThemselves) {
  const std::string input = dir.file("gapped.csv");
  write_gapped(input);
  const CliRun record = run_stickslip({"record", "--input", input, "--gaps", "split", "--output",
                                       dir.file("out.log"), "--interface", "can0"});
  LONGS_EQUAL(2, record.status);
  STRCMP_CONTAINS("stickslip: --gaps split: record streams one continuous signal",
                  record.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("out.log")));
  const CliRun play =
      run_stickslip({"play", "--input", input, "--gaps", "split", "--bus", "loopback"});
  LONGS_EQUAL(2, play.status);
  STRCMP_CONTAINS("stickslip: --gaps split: play streams one continuous signal", play.err.c_str());
  CHECK(record.err.find("replay") == std::string::npos);
  CHECK(play.err.find("replay") == std::string::npos);
}
