// simulate --scene: the scene file gives the same run as the equivalent flags, flags override the
// file, end stops limit the stroke, and a scene's sample rate must match the recording's unless
// --dt sets the model's step.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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
  STRCMP_CONTAINS("--dt 0.001 resamples the recording to the scene's rate", run.err.c_str());
  CHECK_FALSE(test::exists(dir.file("o.csv")));
  const test::CliRun no_model =
      test::run_stickslip({"simulate", "--input", input, "--output", dir.file("o.csv")});
  CHECK_EQUAL(2, no_model.status);
  STRCMP_CONTAINS("--model is required", no_model.err.c_str());
}

// --dt is the model's step, as without a scene: the one the refusal names resamples the recording
// to the scene's rate, and another overrides the scene's rate as the other flags override theirs.
TEST(SceneSimulate, GivenDtOverridesTheScenesSampleRate) {
  const std::string coarse = dir.file("coarse.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration",
                                      "5", "--dt", "0.002", "--output", coarse})
                     .status);
  for (const char* dt : {"0.001", "0.002", "0.0005"}) {
    const std::string out = dir.file(std::string("dt") + dt + ".csv");
    const test::CliRun run =
        test::run_stickslip({"simulate", "--scene", scene_path("linear-seat.toml"), "--input",
                             coarse, "--dt", dt, "--output", out, "--repetitions", "1"});
    CHECK_EQUAL(0, run.status);
    DOUBLES_EQUAL(std::stod(dt), stats_of(run)["dt"].get<double>(), 0.0);
    const std::vector<std::string> rows = test::split_lines(test::read_text(out));
    const auto samples = static_cast<long>(std::lround(5.0 / std::stod(dt))) + 1;
    CHECK_EQUAL(samples + 1, static_cast<long>(rows.size()));  // the header and one row a sample
  }
  // closed-loop reads its recording and scene as simulate does.
  const std::string loop = dir.file("loop.csv");
  const test::CliRun refused =
      test::run_stickslip({"closed-loop", "--scene", scene_path("linear-seat.toml"), "--input",
                           coarse, "--output", loop});
  CHECK_EQUAL(1, refused.status);
  STRCMP_CONTAINS("--dt 0.001 resamples the recording to the scene's rate", refused.err.c_str());
  CHECK_FALSE(test::exists(loop));
  const test::CliRun run =
      test::run_stickslip({"closed-loop", "--scene", scene_path("linear-seat.toml"), "--input",
                           coarse, "--dt", "0.002", "--output", loop});
  CHECK_EQUAL(0, run.status);
  CHECK_EQUAL(2501 + 1, static_cast<long>(test::split_lines(test::read_text(loop)).size()));
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
}

// replay runs the end-stop scene through the ECU node's observer (the loopback bus the node
// speaks on a CAN interface too): its trace equals simulate's on the same (quantised) samples, bit
// for bit, and both report the same contacts.
TEST(SceneSimulate, ReplayWithEndStopsEqualsSimulateBitForBit) {
  const std::string hard = dir.file("hard.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "4", "--duration",
                                      "20", "--dt", "0.001", "--output", hard})
                     .status);
  for (const char* scalar : {"double", "float"}) {
    const std::string replayed = dir.file("replayed.csv"), simulated = dir.file("simulated.csv");
    const test::CliRun replay =
        test::run_stickslip({"replay", "--scene", scene_path("seat-with-end-stops.toml"), "--input",
                             hard, "--bus", "loopback", "--scalar", scalar, "--output", replayed});
    LONGS_EQUAL_TEXT(0, replay.status, replay.err.c_str());
    const test::CliRun simulate = test::run_stickslip(
        {"simulate", "--scene", scene_path("seat-with-end-stops.toml"), "--input", replayed,
         "--scalar", scalar, "--output", simulated, "--repetitions", "1"});
    LONGS_EQUAL_TEXT(0, simulate.status, simulate.err.c_str());
    CHECK_TEXT(test::read_text(replayed) == test::read_text(simulated), scalar);
    const nlohmann::json on_bus = stats_of(replay), offline = stats_of(simulate);
    CHECK_TEXT(on_bus["end_stop_contacts"].get<int>() > 10, scalar);
    CHECK_EQUAL(offline["end_stop_contacts"].get<int>(), on_bus["end_stop_contacts"].get<int>());
  }
}

// An f_a column drives the seat with end stops: simulate's core run agrees with the reference
// with the same force (--integrator reference) to 1e-9 relative RMS of a_x, with the same
// contacts; without the column the run is another one.
TEST(SceneSimulate, EndStopSceneTakesAnActuatorForceColumn) {
  const std::string hard = dir.file("hard.csv"), forced = dir.file("forced.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "4", "--duration",
                                      "20", "--dt", "0.001", "--output", hard})
                     .status);
  const test::Table floor = test::read_table(hard);
  std::string text = "t,a_u,f_a\n";
  char row[128];
  for (std::size_t n = 0; n < floor.rows.size(); ++n) {
    const double t = floor.rows[n][0];
    // Steps every 0.25 s (beyond F_fs = 30 N) and a slow sine: what an actuator holds.
    const double f_a = (static_cast<long>(t / 0.25) % 2 == 0 ? 45.0 : -45.0) +
                       20.0 * std::sin(2.0 * 3.14159265358979 * 0.7 * t);
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g\n", t, floor.rows[n][1], f_a);
    text += row;
  }
  test::write_text(forced, text);
  const std::string core = dir.file("core.csv"), exact = dir.file("exact.csv");
  const test::CliRun run =
      test::run_stickslip({"simulate", "--scene", scene_path("seat-with-end-stops.toml"), "--input",
                           forced, "--output", core, "--repetitions", "1"});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  const test::CliRun reference = test::run_stickslip(
      {"simulate", "--scene", scene_path("seat-with-end-stops.toml"), "--input", forced, "--output",
       exact, "--repetitions", "1", "--integrator", "reference"});
  LONGS_EQUAL_TEXT(0, reference.status, reference.err.c_str());
  const std::vector<double> a_x = test::column(test::read_table(core), 4);
  const std::vector<double> a_ref = test::column(test::read_table(exact), 4);
  CHECK_EQUAL(a_ref.size(), a_x.size());
  double error = 0.0, norm = 0.0;
  for (std::size_t n = 0; n < a_ref.size(); ++n) {
    error += (a_x[n] - a_ref[n]) * (a_x[n] - a_ref[n]);
    norm += a_ref[n] * a_ref[n];
  }
  const double relative = std::sqrt(error / norm);
  if (std::getenv("STICKSLIP_TEST_MARGINS") != nullptr)
    std::printf("\n    [figure] end-stop scene with f_a vs reference: a_x relative RMS %.3e",
                relative);
  CHECK_TRUE(relative <= 1e-9);
  const int contacts = stats_of(run)["end_stop_contacts"].get<int>();
  CHECK_TRUE(contacts > 10);
  CHECK_EQUAL(stats_of(reference)["end_stop_contacts"].get<int>(), contacts);
  // The force matters: the passive run on the same floor is another one.
  const std::string passive = dir.file("passive.csv");
  CHECK_EQUAL(0, test::run_stickslip({"simulate", "--scene", scene_path("seat-with-end-stops.toml"),
                                      "--input", hard, "--output", passive, "--repetitions", "1"})
                     .status);
  CHECK_FALSE(test::read_text(passive) == test::read_text(core));
}
