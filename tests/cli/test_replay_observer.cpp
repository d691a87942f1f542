// replay publishes the observer: its window figures at the end of the stream equal an offline
// recomputation over the same samples of the written run, and the ride comfort equals simulate's.
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "CppUTest/TestHarness.h"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"

using namespace stickslip;

TEST_GROUP(ReplayObserver){};

TEST(ReplayObserver, WindowFiguresEqualTheOfflineOnesForTheSameSamples) {
  test::TempDir dir;
  const std::string input = dir.file("lorry.csv"), replayed = dir.file("replayed.csv"),
                    simulated = dir.file("simulated.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "25", "--dt", "0.001", "--output", input})
                     .status);
  const test::CliRun replay =
      test::run_stickslip({"replay", "--input", input, "--bus", "loopback", "--model", "stick-slip",
                           "--ffk", "45", "--output", replayed});
  CHECK_EQUAL(0, replay.status);
  const nlohmann::json stats = nlohmann::json::parse(test::split_lines(replay.out).back());
  const nlohmann::json& observer = stats["observer"];
  // 25000 updates after the first sample: 25 blocks of 1 s; the 10 s window holds updates
  // 15001..25000, which are rows 15001..25000 of the output.
  DOUBLES_EQUAL(10.0, observer["window_s"].get<double>(), 1e-9);
  const test::Table table = test::read_table(replayed);
  CHECK_EQUAL(25001u, table.rows.size());
  double u_sq = 0.0, x_sq = 0.0;
  unsigned stick_events = 0;
  for (std::size_t n = 15001; n <= 25000; ++n) {
    u_sq += table.rows[n][1] * table.rows[n][1];
    x_sq += table.rows[n][4] * table.rows[n][4];
    stick_events += (table.rows[n][6] != 0.0 && table.rows[n - 1][6] == 0.0) ? 1u : 0u;
  }
  DOUBLES_EQUAL(std::sqrt(x_sq / u_sq), observer["T_ax"].get<double>(), 1e-12);
  CHECK_EQUAL(stick_events, observer["stick_events"].get<unsigned>());
  STRCMP_EQUAL("stick-slip required", observer["regime"].get<std::string>().c_str());
  // Ride comfort of the whole stream: what simulate reports for the same (quantised) samples.
  const test::CliRun simulate =
      test::run_stickslip({"simulate", "--input", replayed, "--output", simulated, "--model",
                           "stick-slip", "--ffk", "45", "--repetitions", "1"});
  CHECK_EQUAL(0, simulate.status);
  const nlohmann::json offline = nlohmann::json::parse(test::split_lines(simulate.out).back());
  for (const char* key : {"seat_weighted_rms", "seat", "vdv", "mtvv"}) {
    DOUBLES_EQUAL(offline[key].get<double>(), stats[key].get<double>(),
                  1e-12 * offline[key].get<double>());
  }
}

// replay --scalar fixed runs the same fixed-point loop as simulate --scalar fixed: bit for bit.
TEST(ReplayObserver, FixedPointReplayEqualsFixedPointSimulateBitForBit) {
  test::TempDir dir;
  const std::string input = dir.file("lorry.csv"), replayed = dir.file("replayed.csv"),
                    simulated = dir.file("simulated.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "20", "--dt", "0.001", "--output", input})
                     .status);
  const test::CliRun replay =
      test::run_stickslip({"replay", "--input", input, "--bus", "loopback", "--model", "stick-slip",
                           "--ffk", "45", "--scalar", "fixed", "--output", replayed});
  CHECK_EQUAL(0, replay.status);
  const test::CliRun simulate =
      test::run_stickslip({"simulate", "--input", replayed, "--output", simulated, "--model",
                           "stick-slip", "--ffk", "45", "--scalar", "fixed", "--repetitions", "1"});
  CHECK_EQUAL(0, simulate.status);
  CHECK_TRUE(test::read_text(replayed) == test::read_text(simulated));
  const nlohmann::json stats = nlohmann::json::parse(test::split_lines(replay.out).back());
  STRCMP_EQUAL("fixed", stats["scalar"].get<std::string>().c_str());
  CHECK_EQUAL(0, stats["saturated_steps"].get<int>());
}
