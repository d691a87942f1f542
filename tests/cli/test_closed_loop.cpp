// stickslip closed-loop against independent computations: the passive loop against simulate (bit
// for bit), the controlled loop's own force fed back into simulate's f_a column (bit for bit: the
// loop's plant is the exact core, the force held over the step after it was computed), the sweep's
// endpoints against single runs, and the refusals; on a scene with end stops, the same two
// equalities with the count of contacts.
#include <cstddef>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"

// CppUTest last: its leak detector redefines new.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

nlohmann::json last_json(const std::string& out) {
  return nlohmann::json::parse(test::split_lines(out).back());
}

// A 20 s lorry-like floor: long enough for many stick-slip cycles, short for the test. At
// 3 m/s^2 RMS the seat of docs/scenes/seat-with-end-stops.toml reaches its +-50 mm stops.
std::string lorry(const test::TempDir& dir, const char* rms_m_per_s2 = "0.6") {
  const std::string input = dir.file("lorry.csv");
  const test::CliRun run =
      test::run_stickslip({"generate", "--kind", "lorry", "--rms", rms_m_per_s2, "--duration", "20",
                           "--dt", "0.001", "--seed", "3", "--output", input});
  CHECK_EQUAL(0, run.status);
  return input;
}

const std::vector<std::string> kSeat = {"--model", "stick-slip", "--ffk", "40", "--ffs", "55"};

std::string end_stop_scene() {
  return std::string(STICKSLIP_SOURCE_DIR) + "/docs/scenes/seat-with-end-stops.toml";
}

std::vector<std::string> with(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

// Cells of columns [first, last) that differ bit for bit between two traces of equal length
// (t,a_u,x_r,v_r,a_x,f_f,stuck,...; the CSVs print doubles round-trip).
std::size_t differing_cells(const test::Table& a, const test::Table& b, std::size_t first,
                            std::size_t last) {
  std::size_t differing = 0;
  for (std::size_t n = 0; n < a.rows.size() && n < b.rows.size(); ++n)
    for (std::size_t c = first; c < last; ++c)
      if (!test::bit_equal(a.rows[n][c], b.rows[n][c])) ++differing;
  return differing;
}

}  // namespace

TEST_GROUP(ClosedLoopCommand){};

TEST(ClosedLoopCommand, PassiveControllerEqualsSimulateBitForBit) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  const test::CliRun simulate = test::run_stickslip(
      with({"simulate", "--input", input, "--output", dir.file("sim.csv"), "--repetitions", "1"},
           kSeat));
  CHECK_EQUAL(0, simulate.status);
  const test::CliRun loop = test::run_stickslip(
      with({"closed-loop", "--input", input, "--output", dir.file("loop.csv"), "--controller",
            "passive", "--a-x-noise", "0.02", "--x-r-noise", "1e-4"},
           kSeat));
  CHECK_EQUAL(0, loop.status);
  const test::Table sim = test::read_table(dir.file("sim.csv"));
  const test::Table closed = test::read_table(dir.file("loop.csv"));
  CHECK_TRUE(sim.ok && closed.ok);
  CHECK_EQUAL(sim.rows.size(), closed.rows.size());
  CHECK_EQUAL(8u, closed.header.size());
  STRCMP_EQUAL("f_a", closed.header[7].c_str());
  for (std::size_t n = 0; n < sim.rows.size(); ++n) {
    for (std::size_t c = 0; c < 7; ++c)
      CHECK_TRUE(test::bit_equal(sim.rows[n][c], closed.rows[n][c]));
    CHECK_TRUE(test::bit_equal(0.0, closed.rows[n][7]));
  }
  const nlohmann::json s = last_json(simulate.out), l = last_json(loop.out);
  for (const auto* run : {"passive", "controlled"}) {
    const nlohmann::json& f = l[run];
    // The same double, not merely close: the same loop and the same statistics.
    CHECK_TRUE(test::bit_equal(s["T_ax"].get<double>(), f["T_ax"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["p_stick"].get<double>(), f["p_stick"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["seat_weighted_rms"].get<double>(),
                               f["seat_weighted_rms"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["floor_weighted_rms"].get<double>(),
                               f["floor_weighted_rms"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["seat"].get<double>(), f["seat"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["vdv"].get<double>(), f["vdv"].get<double>()));
  }
  CHECK_TRUE(test::bit_equal(0.0, l["controlled"]["force_rms"].get<double>()));
  CHECK_TRUE(test::bit_equal(0.0, l["controlled"]["mean_power"].get<double>()));
  CHECK_TRUE(test::bit_equal(1.0, l["seat_weighted_rms_ratio"].get<double>()));
}

// At a 5 ms step the observer's 4 ms acceleration low-pass and its 10 ms leak are one step long
// (a time constant below the step cannot act); the loop runs rather than refusing the step, and
// the passive loop is still simulate's seat bit for bit.
TEST(ClosedLoopCommand, PassiveControllerAtAFiveMillisecondStepEqualsSimulate) {
  test::TempDir dir;
  const std::string input = dir.file("floor.csv");
  CHECK_EQUAL(0, test::run_stickslip({"generate", "--kind", "lorry", "--rms", "1.5", "--duration",
                                      "20", "--dt", "0.005", "--seed", "4", "--output", input})
                     .status);
  const std::vector<std::string> seat = {"--model",     "stick-slip", "--ffk",     "10",
                                         "--ffs",       "35",         "--mass",    "70",
                                         "--stiffness", "9000",       "--damping", "200"};
  const test::CliRun simulate = test::run_stickslip(with(
      {"simulate", "--input", input, "--output", dir.file("sim.csv"), "--repetitions", "1"}, seat));
  CHECK_EQUAL(0, simulate.status);
  const test::CliRun loop = test::run_stickslip(
      with({"closed-loop", "--input", input, "--output", dir.file("loop.csv")}, seat));
  CHECK_EQUAL(0, loop.status);
  const test::Table sim = test::read_table(dir.file("sim.csv"));
  const test::Table closed = test::read_table(dir.file("loop.csv"));
  CHECK_TRUE(sim.ok && closed.ok);
  CHECK_EQUAL(4001u, sim.rows.size());
  CHECK_EQUAL(sim.rows.size(), closed.rows.size());
  CHECK_EQUAL(0u, differing_cells(sim, closed, 0, 7));
  CHECK_TRUE(test::bit_equal(last_json(simulate.out)["T_ax"].get<double>(),
                             last_json(loop.out)["controlled"]["T_ax"].get<double>()));
}

// The loop's trace carries the force that acted over each step; simulate with that f_a column is
// the plant alone, run by simulate's own loop. Equal a_x, x_r and v_r histories prove that the
// loop steps the exact core with the force held over the step after the sample that computed it.
TEST(ClosedLoopCommand, LoopForceFedBackIntoSimulateGivesTheSameSeatBitForBit) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  const std::vector<std::vector<std::string>> controllers = {
      {"--controller", "skyhook-semi", "--gain", "2000", "--a-x-noise", "0.02", "--x-r-noise",
       "3e-5", "--x-r-resolution", "1e-4"},
      {"--controller", "skyhook", "--gain", "1500", "--actuator-lag", "0.005", "--force-limit",
       "150"},
      {"--controller", "groundhook-semi", "--observer", "ideal"},
      {"--controller", "friction-compensation"}};
  for (const auto& controller : controllers) {
    const test::CliRun loop = test::run_stickslip(
        with(with({"closed-loop", "--input", input, "--output", dir.file("loop.csv")}, kSeat),
             controller));
    CHECK_EQUAL(0, loop.status);
    const nlohmann::json l = last_json(loop.out);
    CHECK_TRUE(l["controlled"]["force_rms"].get<double>() > 1.0);  // the force did act
    const test::CliRun simulate =
        test::run_stickslip(with({"simulate", "--input", dir.file("loop.csv"), "--output",
                                  dir.file("sim.csv"), "--repetitions", "1"},
                                 kSeat));
    CHECK_EQUAL(0, simulate.status);
    const test::Table closed = test::read_table(dir.file("loop.csv"));
    const test::Table sim = test::read_table(dir.file("sim.csv"));
    CHECK_EQUAL(closed.rows.size(), sim.rows.size());
    CHECK_EQUAL(0u, differing_cells(sim, closed, 2, 7));  // x_r, v_r, a_x, f_f, stuck
    const nlohmann::json s = last_json(simulate.out);
    CHECK_TRUE(test::bit_equal(s["T_ax"].get<double>(), l["controlled"]["T_ax"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["seat_weighted_rms"].get<double>(),
                               l["controlled"]["seat_weighted_rms"].get<double>()));
  }
}

// With end stops the plant is the end-stop model, as simulate runs the scene: the passive loop is
// simulate --scene, trace, figures and the count of contacts with the stops.
TEST(ClosedLoopCommand, PassiveControllerOnEndStopSceneEqualsSimulateWithTheSameContacts) {
  test::TempDir dir;
  const std::string input = lorry(dir, "3");
  const test::CliRun simulate =
      test::run_stickslip({"simulate", "--input", input, "--scene", end_stop_scene(), "--output",
                           dir.file("sim.csv"), "--repetitions", "1"});
  CHECK_EQUAL(0, simulate.status);
  const test::CliRun loop =
      test::run_stickslip({"closed-loop", "--input", input, "--scene", end_stop_scene(), "--output",
                           dir.file("loop.csv"), "--controller", "passive", "--a-x-noise", "0.02"});
  CHECK_EQUAL(0, loop.status);
  const test::Table sim = test::read_table(dir.file("sim.csv"));
  const test::Table closed = test::read_table(dir.file("loop.csv"));
  CHECK_TRUE(sim.ok && closed.ok);
  CHECK_EQUAL(sim.rows.size(), closed.rows.size());
  CHECK_EQUAL(0u, differing_cells(sim, closed, 0, 7));
  const nlohmann::json s = last_json(simulate.out), l = last_json(loop.out);
  const auto contacts = s["end_stop_contacts"].get<std::uint64_t>();
  CHECK_TRUE(contacts > 0);  // the stops were reached: the end-stop model's contact path ran
  for (const auto* run : {"passive", "controlled"}) {
    const nlohmann::json& f = l[run];
    CHECK_EQUAL(contacts, f["end_stop_contacts"].get<std::uint64_t>());
    CHECK_TRUE(test::bit_equal(s["T_ax"].get<double>(), f["T_ax"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["p_stick"].get<double>(), f["p_stick"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["seat_weighted_rms"].get<double>(),
                               f["seat_weighted_rms"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["vdv"].get<double>(), f["vdv"].get<double>()));
  }
  // Without end stops the key is absent, as simulate's.
  const test::CliRun plain = test::run_stickslip(
      with({"closed-loop", "--input", input, "--output", dir.file("plain.csv")}, kSeat));
  CHECK_EQUAL(0, plain.status);
  CHECK_FALSE(last_json(plain.out)["controlled"].contains("end_stop_contacts"));
}

// The loop's force fed back into simulate's f_a column on the scene with end stops: the same
// seat bit for bit, contacts included, so the loop steps EndStopOscillator::step(a_u, f_a) with
// the force held over the step after the sample that computed it.
TEST(ClosedLoopCommand, LoopForceFedBackIntoSimulateOnEndStopSceneGivesTheSameSeatAndContacts) {
  test::TempDir dir;
  const std::string input = lorry(dir, "3");
  const std::vector<std::vector<std::string>> controllers = {
      {"--controller", "skyhook", "--gain", "1500", "--actuator-lag", "0.005"},
      {"--controller", "skyhook-semi", "--gain", "2000", "--a-x-noise", "0.02", "--x-r-noise",
       "3e-5", "--x-r-resolution", "1e-4"},
      {"--controller", "groundhook-semi", "--observer", "ideal"},
      {"--controller", "friction-compensation"}};
  std::uint64_t most_contacts = 0;
  for (const auto& controller : controllers) {
    const test::CliRun loop =
        test::run_stickslip(with({"closed-loop", "--input", input, "--scene", end_stop_scene(),
                                  "--output", dir.file("loop.csv")},
                                 controller));
    CHECK_EQUAL(0, loop.status);
    const nlohmann::json l = last_json(loop.out);
    CHECK_TRUE(l["controlled"]["force_rms"].get<double>() > 1.0);  // the force did act
    const test::CliRun simulate = test::run_stickslip({"simulate", "--input", dir.file("loop.csv"),
                                                       "--scene", end_stop_scene(), "--output",
                                                       dir.file("sim.csv"), "--repetitions", "1"});
    CHECK_EQUAL(0, simulate.status);
    const test::Table closed = test::read_table(dir.file("loop.csv"));
    const test::Table sim = test::read_table(dir.file("sim.csv"));
    CHECK_EQUAL(closed.rows.size(), sim.rows.size());
    CHECK_EQUAL(0u, differing_cells(sim, closed, 2, 7));  // x_r, v_r, a_x, f_f, stuck
    const nlohmann::json s = last_json(simulate.out);
    const auto contacts = l["controlled"]["end_stop_contacts"].get<std::uint64_t>();
    CHECK_EQUAL(s["end_stop_contacts"].get<std::uint64_t>(), contacts);
    most_contacts = contacts > most_contacts ? contacts : most_contacts;
    CHECK_TRUE(test::bit_equal(s["T_ax"].get<double>(), l["controlled"]["T_ax"].get<double>()));
    CHECK_TRUE(test::bit_equal(s["seat_weighted_rms"].get<double>(),
                               l["controlled"]["seat_weighted_rms"].get<double>()));
  }
  CHECK_TRUE(most_contacts > 0);  // some controlled run did reach the stops
}

TEST(ClosedLoopCommand, SweepEndpointsEqualSingleRunsAtThoseGains) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  const std::vector<std::string> base =
      with({"closed-loop", "--input", input, "--controller", "skyhook-semi", "--a-x-noise", "0.02"},
           kSeat);
  const test::CliRun sweep = test::run_stickslip(
      with(base, {"--output", dir.file("sweep.csv"), "--sweep-gain", "500:2500:3"}));
  CHECK_EQUAL(0, sweep.status);
  const test::Table rows = test::read_table(dir.file("sweep.csv"));
  CHECK_TRUE(rows.ok);
  CHECK_EQUAL(3u, rows.rows.size());
  const char* keys[] = {"seat_weighted_rms", "seat",       "T_ax",      "vdv", "travel",
                        "force_rms",         "force_peak", "mean_power"};
  for (const std::size_t row : {std::size_t{0}, std::size_t{2}}) {
    const std::string gain = row == 0 ? "500" : "2500";
    const test::CliRun single =
        test::run_stickslip(with(base, {"--output", dir.file("one.csv"), "--gain", gain}));
    CHECK_EQUAL(0, single.status);
    const nlohmann::json f = last_json(single.out)["controlled"];
    CHECK_TRUE(test::bit_equal(std::stod(gain), rows.rows[row][0]));
    for (std::size_t k = 0; k < 8; ++k)
      CHECK_TRUE(test::bit_equal(f[keys[k]].get<double>(), rows.rows[row][k + 1]));
  }
  // More damping in the sky: a different point, not a copy of the first.
  CHECK_TRUE(rows.rows[2][6] > rows.rows[0][6]);
}

TEST(ClosedLoopCommand, RefusesAnUnknownControllerAndAForceColumnWithExit2) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  const test::CliRun unknown = test::run_stickslip(with(
      {"closed-loop", "--input", input, "--output", dir.file("loop.csv"), "--controller", "skyhok"},
      kSeat));
  CHECK_EQUAL(2, unknown.status);
  CHECK_TRUE(unknown.err.find("did you mean skyhook") != std::string::npos);
  const test::CliRun sweep_passive =
      test::run_stickslip(with({"closed-loop", "--input", input, "--output", dir.file("loop.csv"),
                                "--sweep-gain", "0:100:3"},
                               kSeat));
  CHECK_EQUAL(2, sweep_passive.status);
  CHECK_TRUE(sweep_passive.err.find("--sweep-gain") != std::string::npos);
  CHECK_FALSE(test::exists(dir.file("loop.csv")));
  // A recording that already carries a force: the loop computes its own, so it is refused.
  test::write_text(dir.file("forced.csv"), "t,a_u,f_a\n0,0,0\n0.001,0.1,1\n0.002,0.2,2\n");
  const test::CliRun with_force = test::run_stickslip(with(
      {"closed-loop", "--input", dir.file("forced.csv"), "--output", dir.file("loop.csv")}, kSeat));
  CHECK_EQUAL(2, with_force.status);
  CHECK_TRUE(with_force.err.find("column 'f_a'") != std::string::npos);
  CHECK_FALSE(test::exists(dir.file("loop.csv")));
  // A gain, lag or fraction out of its range is refused by its option, whichever controller
  // runs (a passive loop would otherwise carry a NaN gain into its JSON).
  for (const auto& [option, value, why] :
       {std::tuple<const char*, const char*, const char*>{"--gain", "nan",
                                                          "must be a finite number >= 0, got nan"},
        {"--actuator-lag", "-1", "must be a finite number >= 0, got -1"},
        {"--force-limit", "0", "must be a finite number > 0, got 0"},
        {"--friction-compensation", "1.5", "must be a fraction in [0, 1], got 1.5"}}) {
    const test::CliRun bad = test::run_stickslip(with(
        {"closed-loop", "--input", input, "--output", dir.file("loop.csv"), option, value}, kSeat));
    CHECK_EQUAL(2, bad.status);
    STRCMP_EQUAL((std::string("stickslip: ") + option + ": " + why + "\n").c_str(),
                 bad.err.c_str());
    CHECK_FALSE(test::exists(dir.file("loop.csv")));
  }
  // A sensor noise is an RMS: a negative or not-a-number one is a mistake, not "no noise".
  for (const char* option : {"--a-x-noise", "--x-r-noise"}) {
    for (const char* value : {"-1", "nan"}) {
      const test::CliRun noise = test::run_stickslip(
          with({"closed-loop", "--input", input, "--output", dir.file("loop.csv"), option, value},
               kSeat));
      CHECK_EQUAL(2, noise.status);
      STRCMP_EQUAL((std::string("stickslip: ") + option + ": must be a finite number >= 0, got " +
                    value + "\n")
                       .c_str(),
                   noise.err.c_str());
      CHECK_FALSE(test::exists(dir.file("loop.csv")));
    }
  }
}

// The loop's seat, estimator and controller run in double: the help offers no other scalar and
// another is refused with exit 2, naming it, before any output.
TEST(ClosedLoopCommand, OffersAndRunsDoubleOnly) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  for (const char* command : {"closed-loop", "plant", "controller"}) {
    const test::CliRun help = test::run_stickslip({command, "--help"});
    CHECK_EQUAL(0, help.status);
    const std::string::size_type at = help.out.find("--scalar");
    CHECK_TRUE(at != std::string::npos);
    const std::string line = help.out.substr(at, help.out.find('\n', at) - at);
    CHECK_TRUE(line.find("double") != std::string::npos);
    CHECK_TRUE(line.find("float") == std::string::npos);
    CHECK_TRUE(line.find("fixed") == std::string::npos);
  }
  for (const char* scalar : {"float", "fixed", "fixed32"}) {
    const test::CliRun run = test::run_stickslip(with(
        {"closed-loop", "--input", input, "--output", dir.file("loop.csv"), "--scalar", scalar},
        kSeat));
    CHECK_EQUAL(2, run.status);
    CHECK_TRUE(run.err.find(std::string("--scalar ") + scalar + ": ") != std::string::npos);
    CHECK_FALSE(test::exists(dir.file("loop.csv")));
  }
}
