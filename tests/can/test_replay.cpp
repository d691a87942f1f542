// Replay over the loopback bus equals simulate on the quantised input bit for bit; the ecu
// command runs the node alone until --frames; the replay reports its fault counters.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include <nlohmann/json.hpp>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/scene_file.hpp"
#include "stickslip/port/loopback_transport.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"

using namespace stickslip;
using stickslip::test::CliRun;
using stickslip::test::run_stickslip;

namespace {

// Writes t and the quantised a_u (quantise -> decode, the codec's contract) of a recording.
void write_quantised_csv(const std::string& in, const std::string& out) {
  const host::SampledSignal signal = host::read_signal_csv(in);
  std::FILE* file = std::fopen(out.c_str(), "w");
  std::fprintf(file, "t,a_u\n");
  for (std::size_t n = 0; n < signal.t_s.size(); ++n)
    std::fprintf(file, "%.17g,%.17g\n", signal.t_s[n],
                 can::quantised_input(signal.a_u_m_per_s2[n]));
  std::fclose(file);
}

nlohmann::json last_json_line(const std::string& out) {
  const auto lines = stickslip::test::split_lines(out);
  return nlohmann::json::parse(lines.back());
}

// Runs the ECU node of `request` on the in-process loopback bus and sends it the recording's
// frames in lock step, each answered (SeatMotion) before the next goes out; checks that every
// frame was answered.
host::EcuResult run_ecu_in_lock_step(const host::EcuRequest& request,
                                     const host::BusRecording& recording) {
  auto tester = port::make_loopback_transport();
  CHECK(tester->open("loopback") == port::TransportStatus::ok);
  const port::ReceiveFilter motion{can::kSeatMotion.id, can::kStandardIdMask};
  tester->set_filters(&motion, 1);
  host::EcuResult result;
  std::thread ecu([&] { result = host::run_ecu(request); });
  for (int wait = 0; wait < 1000 && port::loopback_endpoints() < 2; ++wait)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  LONGS_EQUAL(2, port::loopback_endpoints());
  std::uint64_t answered = 0;
  for (const can::Frame& frame : recording.frames) {
    CHECK(tester->send(frame) == port::TransportStatus::ok);
    can::Frame answer;
    answered += tester->receive(answer, 1000) == port::TransportStatus::ok;
  }
  ecu.join();
  LONGS_EQUAL(recording.frames.size(), answered);
  return result;
}

}  // namespace

TEST_GROUP(Replay) {
  stickslip::test::TempDir dir;
};

TEST(Replay, LoopbackReplayOfA120sLorryRecordingEqualsSimulateOnTheQuantisedInputBitForBit) {
  const std::string lorry = dir.file("lorry.csv"), quantised = dir.file("quantised.csv");
  const std::string replayed = dir.file("replayed.csv"), simulated = dir.file("simulated.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration", "120",
                                "--dt", "0.001", "--seed", "1", "--output", lorry})
                     .status);
  write_quantised_csv(lorry, quantised);
  const std::vector<std::string> model = {"--model", "stick-slip", "--mass", "88.4",  "--stiffness",
                                          "11500",   "--damping",  "504",    "--ffk", "45"};
  std::vector<std::string> replay = {"replay",   "--input",  lorry,   "--bus",
                                     "loopback", "--output", replayed};
  replay.insert(replay.end(), model.begin(), model.end());
  const CliRun r = run_stickslip(replay);
  LONGS_EQUAL(0, r.status);
  std::vector<std::string> simulate = {"simulate", "--input",       quantised, "--output",
                                       simulated,  "--repetitions", "1"};
  simulate.insert(simulate.end(), model.begin(), model.end());
  const CliRun s = run_stickslip(simulate);
  LONGS_EQUAL(0, s.status);

  const std::string replayed_text = stickslip::test::read_text(replayed);
  const std::string simulated_text = stickslip::test::read_text(simulated);
  // header + one row per sample (counted without splitting: 1e5 small strings are slow under
  // CppUTest's leak detector)
  LONGS_EQUAL(120002, std::count(replayed_text.begin(), replayed_text.end(), '\n'));
  CHECK_TRUE(replayed_text == simulated_text);  // bit for bit, every column of every row
  // The quantisation did happen (the original a_u is not on 2^-10 steps).
  CHECK_FALSE(stickslip::test::read_text(lorry).substr(0, 200) == replayed_text.substr(0, 200));

  const nlohmann::json replay_stats = last_json_line(r.out);
  const nlohmann::json simulate_stats = last_json_line(s.out);
  for (const char* key : {"samples", "rms_u", "rms_x", "T_ax", "p_stick", "K", "events"})
    CHECK_TRUE(replay_stats[key] == simulate_stats[key]);
  LONGS_EQUAL(0, replay_stats["faults"]["faults"].get<int>());
  LONGS_EQUAL(120001, replay_stats["faults"]["accepted"].get<int>());
  STRCMP_EQUAL("loopback", replay_stats["bus"].get<std::string>().c_str());
  CHECK(r.out.find("faults 0: frames 120001 accepted 120001") != std::string::npos);
}

TEST(Replay, FloatRunsAndOtherLawsAgreeBitForBitToo) {
  const std::string wideband = dir.file("wideband.csv"), quantised = dir.file("quantised.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "wideband", "--rms", "2", "--duration", "5",
                                "--dt", "0.001", "--seed", "3", "--output", wideband})
                     .status);
  write_quantised_csv(wideband, quantised);
  for (const char* law : {"stribeck", "smooth", "signum"}) {
    const std::vector<std::string> model = {"--model", law,  "--ffk",    "30",
                                            "--ffs",   "40", "--scalar", "float"};
    std::vector<std::string> replay = {"replay", "--input", wideband, "--output",
                                       dir.file("r.csv")};
    replay.insert(replay.end(), model.begin(), model.end());
    LONGS_EQUAL(0, run_stickslip(replay).status);
    std::vector<std::string> simulate = {"simulate",        "--input",       quantised, "--output",
                                         dir.file("s.csv"), "--repetitions", "1"};
    simulate.insert(simulate.end(), model.begin(), model.end());
    LONGS_EQUAL(0, run_stickslip(simulate).status);
    CHECK_TRUE(stickslip::test::read_text(dir.file("r.csv")) ==
               stickslip::test::read_text(dir.file("s.csv")));
  }
}

TEST(Replay, SaturatedInputIsReportedAndClipped) {
  const std::string input = dir.file("big.csv");
  stickslip::test::write_text(input, "t,a_u\n0,0.5\n0.001,40\n0.002,-100\n0.003,0.25\n");
  const CliRun r = run_stickslip(
      {"replay", "--input", input, "--output", dir.file("o.csv"), "--model", "linear"});
  LONGS_EQUAL(0, r.status);
  CHECK(r.out.find("2 input samples saturated") != std::string::npos);
  LONGS_EQUAL(2, last_json_line(r.out)["faults"]["sender_saturated"].get<int>());
  const auto lines = stickslip::test::split_lines(stickslip::test::read_text(dir.file("o.csv")));
  CHECK(lines[2].rfind("0.001,31.9990234375,", 0) == 0);
}

TEST(Replay, RealtimeRateTakesTheRecordingsDuration) {
  const std::string input = dir.file("short.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "harmonic", "--rms", "1", "--duration", "0.2",
                                "--dt", "0.001", "--frequency", "5", "--output", input})
                     .status);
  const auto start = std::chrono::steady_clock::now();
  LONGS_EQUAL(0, run_stickslip({"replay", "--input", input, "--output", dir.file("o.csv"),
                                "--model", "stick-slip", "--rate", "realtime"})
                     .status);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(elapsed >= 0.19);
  LONGS_EQUAL(2, run_stickslip({"replay", "--input", input, "--output", dir.file("o.csv"),
                                "--model", "stick-slip", "--rate", "warp"})
                     .status);
}

TEST(Replay, UnknownBusFailsWithOneLine) {
  const std::string input = dir.file("in.csv");
  stickslip::test::write_text(input, "t,a_u\n0,0.5\n0.001,0.25\n");
  const CliRun r = run_stickslip({"replay", "--input", input, "--output", dir.file("o.csv"),
                                  "--model", "linear", "--bus", "nosuchcan9"});
  LONGS_EQUAL(1, r.status);
  CHECK(r.err.rfind("stickslip: --bus nosuchcan9: cannot open the bus", 0) == 0);
  CHECK_FALSE(stickslip::test::exists(dir.file("o.csv")));
}

TEST_GROUP(EcuCommand) {
  stickslip::test::TempDir dir;
};

TEST(EcuCommand, NodeAloneConsumesFramesUntilTheFrameLimitAndReportsCounters) {
  host::EcuRequest request;
  request.bus = "loopback";
  request.setup.params.model = FrictionModel::stick_slip;
  request.setup.params.integrator = Integrator::exact;
  request.setup.params.kinetic_friction_n = request.setup.params.static_friction_n = 45.0;
  request.max_frames = 60;
  request.output_path = dir.file("ecu.csv");
  request.sample_index_path = dir.file("ecu.idx");
  host::EcuResult result;
  std::thread ecu([&] { result = host::run_ecu(request); });
  auto tester = port::make_loopback_transport();
  CHECK(tester->open("loopback") == port::TransportStatus::ok);
  // The node announces itself by answering: send sample 0 until an output comes back (copies
  // that reach it are duplicates).
  can::Frame answer;
  bool answered = false;
  for (int attempt = 0; attempt < 300 && !answered; ++attempt) {
    if (attempt % 20 == 0) tester->send(can::make_input_frame(0.5, 0));
    answered = tester->receive(answer, 10) == port::TransportStatus::ok;
  }
  CHECK_TRUE(answered);
  for (std::uint64_t n = 1; n <= 50; ++n)
    tester->send(can::make_input_frame(0.5 + 0.001 * static_cast<double>(n), n));
  can::Frame foreign;
  foreign.id = 0x321;
  foreign.length = 8;
  tester->send(foreign);
  // Another node's outputs are ignored and not counted towards --frames.
  can::Frame other_node;
  other_node.id = can::kSeatStats.id;
  other_node.length = 8;
  tester->send(other_node);
  // Up to the frame limit with duplicates of the last sample (the node stops at 60).
  for (int i = 0; i < 10; ++i) tester->send(can::make_input_frame(0.55, 50));
  ecu.join();
  LONGS_EQUAL(61, result.frames_received);
  LONGS_EQUAL(1, result.faults.ignored_output);
  LONGS_EQUAL(51, result.faults.accepted);
  LONGS_EQUAL(1, result.faults.foreign_frames);
  LONGS_EQUAL(60 - 52, result.faults.duplicate);
  LONGS_EQUAL(51 * 2 + 6 * 2, result.output_frames);  // motion + force; stats + scene every 10th
  const auto json = nlohmann::json::parse(result.json);
  LONGS_EQUAL(51, json["samples"].get<int>());
  LONGS_EQUAL(1, json["faults"]["foreign_frames"].get<int>());
  const auto lines = stickslip::test::split_lines(stickslip::test::read_text(request.output_path));
  LONGS_EQUAL(52, lines.size());
  STRCMP_EQUAL("t,a_u,x_r,v_r,a_x,f_f,stuck", lines[0].c_str());
  // The sender's sample number of every row.
  LONGS_EQUAL(0, json["first_sample"].get<int>());
  LONGS_EQUAL(50, json["last_sample"].get<int>());
  LONGS_EQUAL(0, json["bus_down"].get<int>());
  const auto index =
      stickslip::test::split_lines(stickslip::test::read_text(request.sample_index_path));
  LONGS_EQUAL(52, index.size());
  STRCMP_EQUAL("n,sample,held", index[0].c_str());
  STRCMP_EQUAL("0,0,0", index[1].c_str());
  STRCMP_EQUAL("50,50,0", index[51].c_str());
}

TEST(EcuCommand, NodeAloneWritesWhatReplayWritesForTheSameFrames) {
  // What the guest test does with canplayer: the frames of a recording sent by another endpoint
  // to `ecu`; its CSV must equal replay's (and so simulate's on the quantised input).
  const std::string lorry = dir.file("lorry.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "0.35", "--duration", "10",
                                "--dt", "0.001", "--seed", "2", "--output", lorry})
                     .status);
  LONGS_EQUAL(0, run_stickslip({"replay", "--input", lorry, "--output", dir.file("replay.csv"),
                                "--model", "stick-slip", "--ffk", "45"})
                     .status);
  const host::BusRecording recording = host::frames_from_csv(lorry);
  host::EcuRequest request;
  request.bus = "loopback";
  request.setup.params.model = FrictionModel::stick_slip;
  request.setup.params.integrator = Integrator::exact;
  request.setup.params.kinetic_friction_n = request.setup.params.static_friction_n = 45.0;
  request.max_frames = recording.frames.size();
  request.output_path = dir.file("ecu.csv");
  const host::EcuResult result = run_ecu_in_lock_step(request, recording);
  LONGS_EQUAL(recording.frames.size(), result.faults.accepted);
  LONGS_EQUAL(0, result.faults.faults());
  CHECK_TRUE(stickslip::test::read_text(dir.file("replay.csv")) ==
             stickslip::test::read_text(request.output_path));
}

// `ecu --scene docs/scenes/seat-with-end-stops.toml` needs a CAN interface; here its node runs
// on the in-process loopback bus with the setup that scene gives (read as the CLI reads it), fed
// the frames of a recording hard enough to reach the stops: its CSV equals replay's with the
// same scene, and it reports the same end-stop contacts.
TEST(EcuCommand, NodeAloneRunsAnEndStopSceneAsReplayDoes) {
  std::string scene_path = STICKSLIP_DBC_PATH;
  scene_path.replace(scene_path.find("can/stickslip.dbc"), std::string::npos,
                     "scenes/seat-with-end-stops.toml");
  const host::Scene scene = host::read_scene_file(scene_path);
  const std::string lorry = dir.file("lorry.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "4", "--duration", "10",
                                "--dt", "0.001", "--seed", "2", "--output", lorry})
                     .status);
  const CliRun replay = run_stickslip(
      {"replay", "--input", lorry, "--output", dir.file("replay.csv"), "--scene", scene_path});
  LONGS_EQUAL_TEXT(0, replay.status, replay.err.c_str());
  const host::BusRecording recording = host::frames_from_csv(lorry);
  host::EcuRequest request;
  request.bus = "loopback";
  request.setup.params = scene.params;
  request.setup.params.dt_s = 0.001;
  request.setup.effects = scene.effects;
  request.setup.stops = scene.stops;
  request.max_frames = recording.frames.size();
  request.output_path = dir.file("ecu.csv");
  const host::EcuResult result = run_ecu_in_lock_step(request, recording);
  LONGS_EQUAL(0, result.faults.faults());
  CHECK_TRUE(stickslip::test::read_text(dir.file("replay.csv")) ==
             stickslip::test::read_text(request.output_path));
  const auto json = nlohmann::json::parse(result.json);
  const int contacts = last_json_line(replay.out)["end_stop_contacts"].get<int>();
  CHECK_TRUE(contacts > 5);
  LONGS_EQUAL(contacts, json["end_stop_contacts"].get<int>());
}

TEST(EcuCommand, StopFlagEndsTheRun) {
  host::EcuRequest request;
  request.bus = "loopback";
  request.setup.params.model = FrictionModel::linear;
  request.setup.params.integrator = Integrator::exact;
  volatile std::sig_atomic_t stop = 0;
  request.stop = &stop;
  std::thread ecu([&] { host::run_ecu(request); });
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  stop = 1;
  ecu.join();  // returns within one poll period
  CHECK_EQUAL(1, stop);
}

TEST_GROUP(PlayCommand) {
  stickslip::test::TempDir dir;
};

TEST(PlayCommand, SendsEveryFrameOfTheRecordingAtTheGivenSpeed) {
  const std::string input = dir.file("short.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "harmonic", "--rms", "1", "--duration", "0.2",
                                "--dt", "0.001", "--frequency", "5", "--output", input})
                     .status);
  auto listener = port::make_loopback_transport();
  CHECK(listener->open("loopback") == port::TransportStatus::ok);
  host::PlayRequest request;
  request.input_path = input;
  request.bus = "loopback";
  request.speed = 4.0;  // 201 frames, 0.05 s
  const auto start = std::chrono::steady_clock::now();
  const host::PlayResult result = host::play_file(request);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(elapsed >= 0.049);
  LONGS_EQUAL(201, result.frames);
  LONGS_EQUAL(201, result.attempted);
  LONGS_EQUAL(201, result.sent);
  LONGS_EQUAL(0, result.not_sent);
  // On the bus: the recording's frames, in order.
  const host::BusRecording recording = host::frames_from_csv(input);
  for (std::size_t n = 0; n < recording.frames.size(); ++n) {
    can::Frame frame;
    CHECK(listener->receive(frame, 100) == port::TransportStatus::ok);
    LONGS_EQUAL(n, can::decode_payload(frame.data).sample_counter);
    CHECK(std::equal(frame.data, frame.data + 8, recording.frames[n].data));
  }
  const auto json = nlohmann::json::parse(result.json);
  LONGS_EQUAL(201, json["sent"].get<int>());
  CHECK(json["first_not_sent"].is_null());
}

TEST(PlayCommand, RefusesASpeedThatIsNotAPositiveFactor) {
  const std::string input = dir.file("in.csv");
  stickslip::test::write_text(input, "t,a_u\n0,0.5\n0.001,0.25\n");
  const CliRun r = run_stickslip({"play", "--input", input, "--bus", "loopback", "--speed", "0"});
  LONGS_EQUAL(2, r.status);
  CHECK(r.err.rfind("stickslip: --speed: must be a positive factor", 0) == 0);
}
