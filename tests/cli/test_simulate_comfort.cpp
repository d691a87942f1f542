// simulate reports ISO 2631-1 ride comfort (Wk) of the run: the same figures an offline
// RideComfort gives over the written a_u and a_x columns.
#include <string>

#include <nlohmann/json.hpp>

#include "CppUTest/TestHarness.h"
#include "stickslip/metrics/ride_comfort.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"

using namespace stickslip;

TEST_GROUP(SimulateComfort){};

TEST(SimulateComfort, StatsCarryTheWeightedFiguresOfTheWrittenRun) {
  test::TempDir dir;
  const std::string input = dir.file("lorry.csv"), output = dir.file("out.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "30", "--dt", "0.001", "--output", input})
                     .status);
  const test::CliRun run =
      test::run_stickslip({"simulate", "--input", input, "--output", output, "--model",
                           "stick-slip", "--ffk", "45", "--repetitions", "1"});
  CHECK_EQUAL(0, run.status);
  const auto lines = test::split_lines(run.out);
  const nlohmann::json stats = nlohmann::json::parse(lines.back());
  const test::Table table = test::read_table(output);
  CHECK_TRUE(table.ok);
  RideComfort<double> comfort;
  CHECK_TRUE(comfort.configure(ComfortWeighting::wk, 1000.0).ok());
  for (const auto& row : table.rows) comfort.add_sample(row[1], row[4]);  // a_u, a_x
  const double seat = stats["seat_weighted_rms"].get<double>();
  DOUBLES_EQUAL(comfort.seat_weighted_rms(), seat, 1e-12 * seat);
  DOUBLES_EQUAL(comfort.floor_weighted_rms(), stats["floor_weighted_rms"].get<double>(),
                1e-12 * seat);
  DOUBLES_EQUAL(comfort.seat_ratio(), stats["seat"].get<double>(), 1e-12);
  DOUBLES_EQUAL(comfort.seat_vdv(), stats["vdv"].get<double>(), 1e-12 * comfort.seat_vdv());
  DOUBLES_EQUAL(comfort.seat_mtvv(), stats["mtvv"].get<double>(), 1e-12 * comfort.seat_mtvv());
  CHECK_TRUE(stats["seat"].get<double>() > 0.5 && stats["seat"].get<double>() < 1.5);
  STRCMP_EQUAL("stick-slip required", stats["regime"].get<std::string>().c_str());
}
