// simulate --scene: the scene file gives the same run as the equivalent flags, flags override the
// file, end stops limit the stroke, and a scene's sample rate must match the recording's.
#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "CppUTest/TestHarness.h"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"

using namespace stickslip;

namespace {

std::string scene_path(const char* name) {
  return std::string(STICKSLIP_SOURCE_DIR) + "/docs/scenes/" + name;
}

nlohmann::json stats_of(const test::CliRun& run) {
  return nlohmann::json::parse(test::split_lines(run.out).back());
}

}  // namespace

TEST_GROUP(SceneSimulate) {
  test::TempDir dir;
  std::string input;
  void setup() override {
    input = dir.file("lorry.csv");
    CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35",
                                        "--duration", "20", "--dt", "0.001", "--output", input})
                       .status);
  }
};

TEST(SceneSimulate, SceneFileGivesTheSameRunAsTheEquivalentFlags) {
  const std::string a = dir.file("scene.csv"), b = dir.file("flags.csv");
  const test::CliRun by_scene =
      test::run_stickslip({"simulate", "--scene", scene_path("lorry-seat-stick-slip.toml"),
                           "--input", input, "--output", a, "--repetitions", "1"});
  CHECK_EQUAL(0, by_scene.status);
  const test::CliRun by_flags = test::run_stickslip(
      {"simulate",   "--input",       input,   "--output", b,      "--model",
       "stick-slip", "--integrator",  "exact", "--mass",   "88.4", "--stiffness",
       "11500",      "--damping",     "504",   "--ffk",    "45",   "--ffs",
       "45",         "--repetitions", "1"});
  CHECK_EQUAL(0, by_flags.status);
  CHECK_TRUE(test::read_text(a) == test::read_text(b));
  nlohmann::json s1 = stats_of(by_scene), s2 = stats_of(by_flags);
  for (const char* volatile_key : {"ns_per_sample", "output"}) {
    s1.erase(volatile_key);
    s2.erase(volatile_key);
  }
  CHECK_TRUE(s1 == s2);
}

TEST(SceneSimulate, FlagsOverrideTheScene) {
  const std::string a = dir.file("scene.csv"), b = dir.file("flags.csv");
  CHECK_EQUAL(0,
              test::run_stickslip({"simulate", "--scene", scene_path("lorry-seat-stick-slip.toml"),
                                   "--ffk", "15", "--damping", "0", "--input", input, "--output", a,
                                   "--repetitions", "1"})
                  .status);
  CHECK_EQUAL(
      0, test::run_stickslip({"simulate", "--input", input, "--output", b, "--model", "stick-slip",
                              "--ffk", "15", "--ffs", "45", "--damping", "0", "--repetitions", "1"})
             .status);
  CHECK_TRUE(test::read_text(a) == test::read_text(b));
}

// Driven hard (RMS 4 m/s^2), the seat with stops at +-50 mm stays near its stroke; without
// the stops the same seat travels much further.
TEST(SceneSimulate, EndStopsLimitTheStroke) {
  const std::string hard = dir.file("hard.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "4", "--duration",
                                      "20", "--dt", "0.001", "--output", hard})
                     .status);
  const std::string with = dir.file("with.csv"), without = dir.file("without.csv");
  const test::CliRun run =
      test::run_stickslip({"simulate", "--scene", scene_path("seat-with-end-stops.toml"), "--input",
                           hard, "--output", with, "--repetitions", "1"});
  CHECK_EQUAL(0, run.status);
  CHECK_EQUAL(0, test::run_stickslip({"simulate", "--input", hard, "--output", without, "--model",
                                      "stick-slip", "--ffk", "30", "--repetitions", "1"})
                     .status);
  const auto largest = [](const std::string& path) {
    double m = 0.0;
    for (double x : test::column(test::read_table(path), 2)) m = std::max(m, std::fabs(x));
    return m;
  };
  const double stopped = largest(with), free_stroke = largest(without);
  CHECK_TRUE(free_stroke > 0.08);     // the free seat goes well past 50 mm
  CHECK_TRUE(stopped > 0.05);         // the stopped one reaches its stops
  CHECK_TRUE(stopped < 0.05 + 0.02);  // and is held near them (k_s = 2e5 N/m)
  CHECK_EQUAL(0, stats_of(run)["state_resets"].get<int>());
}

TEST(SceneSimulate, SceneSampleRateMustMatchTheRecording) {
  const std::string coarse = dir.file("coarse.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "5", "--dt", "0.002", "--output", coarse})
                     .status);
  const test::CliRun run =
      test::run_stickslip({"simulate", "--scene", scene_path("linear-seat.toml"), "--input", coarse,
                           "--output", dir.file("o.csv")});
  CHECK_EQUAL(1, run.status);
  STRCMP_CONTAINS("sample_rate_hz = 1000", run.err.c_str());
  const test::CliRun no_model =
      test::run_stickslip({"simulate", "--input", input, "--output", dir.file("o.csv")});
  CHECK_EQUAL(2, no_model.status);
  STRCMP_CONTAINS("--model is required", no_model.err.c_str());
}

// The bus commands take the same scene files: replay with the scene equals replay with the flags,
// and a scene naming identifiers other than the frame layout's is refused, not ignored.
TEST(SceneSimulate, ReplayTakesTheSceneAndChecksItsCanIds) {
  const std::string a = dir.file("scene.csv"), b = dir.file("flags.csv");
  CHECK_EQUAL(0, test::run_stickslip({"replay", "--scene", scene_path("lorry-seat-stick-slip.toml"),
                                      "--input", input, "--bus", "loopback", "--output", a})
                     .status);
  CHECK_EQUAL(0, test::run_stickslip({"replay", "--input", input, "--bus", "loopback", "--output",
                                      b, "--model", "stick-slip", "--ffk", "45", "--ffs", "45"})
                     .status);
  CHECK_TRUE(test::read_text(a) == test::read_text(b));
  const std::string other = dir.file("other-ids.toml");
  test::write_text(other, "[scene]\neffects = [\"spring\", \"damper\"]\n[can]\ninput_id = 0x123\n");
  const test::CliRun refused =
      test::run_stickslip({"replay", "--scene", other, "--input", input, "--bus", "loopback",
                           "--output", dir.file("x.csv")});
  CHECK_EQUAL(2, refused.status);
  STRCMP_CONTAINS("input_id = 0x123", refused.err.c_str());
  const test::CliRun stops =
      test::run_stickslip({"replay", "--scene", scene_path("seat-with-end-stops.toml"), "--input",
                           input, "--bus", "loopback", "--output", dir.file("y.csv")});
  CHECK_EQUAL(2, stops.status);
  STRCMP_CONTAINS("without end stops", stops.err.c_str());
}
