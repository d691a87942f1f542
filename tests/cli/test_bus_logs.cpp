// CAN logs through the real executable: record stamps the wall clock (checked with can-utils'
// log2asc and python-can), replay runs a log at the log's own rate and keeps its time stamps,
// other traffic on the bus is no fault, --no-e2e takes plain sensor frames, the reduced output
// set and the output cycle thin the node's frames, statistics are "not available" until
// observed, and the bus load's exact bit count agrees with an independent one.
#include <sys/wait.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/frame_bits.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

struct RealRun {
  int status;
  std::string out, err;
};

// The stickslip executable itself, as a user runs it.
RealRun run_real(const test::TempDir& dir, const std::vector<std::string>& arguments) {
  std::string command = std::string("'") + STICKSLIP_EXECUTABLE + "'";
  for (const std::string& argument : arguments) command += " '" + argument + "'";
  const std::string out = dir.file(".out.txt"), err = dir.file(".err.txt");
  command += " >'" + out + "' 2>'" + err + "'";
  const int raw = std::system(command.c_str());
  RealRun run{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, test::read_text(out), test::read_text(err)};
  std::remove(out.c_str());
  std::remove(err.c_str());
  return run;
}

// A shell command's standard output (python-can, log2asc).
std::string shell_output(const test::TempDir& dir, const std::string& command) {
  const std::string out = dir.file(".shell.txt");
  CHECK_EQUAL(0, std::system((command + " >'" + out + "'").c_str()));
  const std::string text = test::read_text(out);
  std::remove(out.c_str());
  return text;
}

nlohmann::json last_json(const RealRun& run) {
  return nlohmann::json::parse(test::split_lines(run.out).back());
}

double a_u_of(std::uint64_t n) {
  return 2.0 * std::sin(0.05 * static_cast<double>(n));
}

// SeatInput frames n = 0..count-1 every interval_us from start_us on `interface`.
std::vector<host::LoggedFrame> input_log(std::uint64_t count, std::uint64_t start_us,
                                         std::uint64_t interval_us, const std::string& interface) {
  std::vector<host::LoggedFrame> log;
  for (std::uint64_t n = 0; n < count; ++n)
    log.push_back({start_us + n * interval_us, interface, can::make_input_frame(a_u_of(n), n)});
  return log;
}

std::uint64_t now_us() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

bool have(const char* program) {
  return std::system((std::string("command -v ") + program + " >/dev/null 2>&1").c_str()) == 0;
}

std::map<std::uint32_t, std::size_t> frames_by_id(const std::vector<host::LoggedFrame>& log) {
  std::map<std::uint32_t, std::size_t> count;
  for (const host::LoggedFrame& entry : log) ++count[entry.frame.id];
  return count;
}

const std::string kNode[] = {"--model", "stick-slip", "--ffk", "45"};

std::vector<std::string> replay_args(const std::string& input, const std::string& output,
                                     std::vector<std::string> more = {}) {
  std::vector<std::string> args{"replay", "--input", input, "--output", output};
  args.insert(args.end(), std::begin(kNode), std::end(kNode));
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

TEST_GROUP(BusLogs) {
  test::TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

// Says "SKIPPED:" without can-utils (tests/cli/CMakeLists.txt reports it as skipped).
TEST_GROUP(RecordCanUtils) {
  test::TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

TEST(RecordCanUtils, RecordStampsTheWallClockSoLog2ascWritesOneHeaderAndPythonCanReadsTheTimes) {
  if (!have("log2asc")) {
    std::printf("\nSKIPPED: log2asc not found (Debian package can-utils; tools/install-deps.sh)\n");
    return;
  }
  const std::string csv = dir.file("lorry.csv"), log = dir.file("lorry.log");
  CHECK_EQUAL(0, run_real(dir, {"generate", "--kind", "lorry", "--rms", "1", "--duration", "30",
                                "--dt", "0.001", "--output", csv})
                     .status);
  const std::uint64_t before_us = now_us();
  CHECK_EQUAL(0, run_real(dir, {"record", "--input", csv, "--output", log}).status);
  const std::uint64_t after_us = now_us();
  const std::vector<host::LoggedFrame> frames = host::read_candump_log(log);
  LONGS_EQUAL(30001, frames.size());
  // The first frame carries the wall clock of the run, the others the recording's time line.
  CHECK(frames[0].time_us >= before_us && frames[0].time_us <= after_us);
  for (std::size_t n = 0; n < frames.size(); ++n)
    CHECK_EQUAL(frames[0].time_us + 1000u * n, frames[n].time_us);

  const std::string asc = dir.file("lorry.asc");
  CHECK_EQUAL(0, std::system(("log2asc -I '" + log + "' -O '" + asc + "' vcan0").c_str()));
  std::size_t headers = 0;
  for (const std::string& line : test::split_lines(test::read_text(asc)))
    headers += line.rfind("date ", 0) == 0;
  LONGS_EQUAL(1, headers);
  // python-can reads the ASC (times since the first frame) and the candump log (absolute).
  const std::vector<std::string> times = test::split_lines(shell_output(
      dir,
      "/usr/bin/python3 -c \"import can,sys\nfor a,b in zip(can.ASCReader(sys.argv[1]), "
      "can.CanutilsLogReader(sys.argv[2])): print(repr(a.timestamp), repr(b.timestamp))\" '" +
          asc + "' '" + log + "'"));
  LONGS_EQUAL(frames.size(), times.size());
  for (std::size_t n = 0; n < frames.size(); n += 997) {
    double relative = 0.0, absolute = 0.0;
    CHECK_EQUAL(2, std::sscanf(times[n].c_str(), "%lf %lf", &relative, &absolute));
    // Both formats hold microseconds: the same microsecond is within half of one.
    CHECK(std::fabs(relative - static_cast<double>(frames[n].time_us - frames[0].time_us) / 1e6) <
          0.5e-6);
    CHECK(std::fabs(absolute - static_cast<double>(frames[n].time_us) / 1e6) < 0.5e-6);
  }
}

TEST(BusLogs, ReplayRunsA500HzLogAtItsOwnRateAndRefusesADtThatContradictsIt) {
  const std::string log = dir.file("fast.log"), out = dir.file("out.csv");
  host::write_candump_log(log, input_log(1001, 1700000000000000u, 2000, "can1"));
  const RealRun run = run_real(dir, replay_args(log, out));
  CHECK_EQUAL(0, run.status);
  const nlohmann::json stats = last_json(run);
  STRCMP_EQUAL("log", stats["dt_source"].get<std::string>().c_str());
  const test::Table table = test::read_table(out);
  const std::vector<double> t = test::column(table, 0);
  LONGS_EQUAL(1001, t.size());
  for (std::size_t n = 0; n < t.size(); ++n) CHECK_EQUAL(static_cast<double>(n) * 0.002, t[n]);

  // Within the stated 1 %: the given --dt; beyond: refused, one line naming the file and rate.
  CHECK_EQUAL(0, run_real(dir, replay_args(log, out, {"--dt", "0.00201"})).status);
  std::remove(out.c_str());
  const RealRun refused = run_real(dir, replay_args(log, out, {"--dt", "0.001"}));
  CHECK_EQUAL(2, refused.status);
  LONGS_EQUAL(1, test::split_lines(refused.err).size());
  STRCMP_CONTAINS(log.c_str(), refused.err.c_str());
  STRCMP_CONTAINS("500 Hz", refused.err.c_str());
  CHECK_FALSE(test::exists(out));
  // Time stamps that are not the stream's (a capture of a faster playback): --retime runs --dt.
  const RealRun retimed = run_real(dir, replay_args(log, out, {"--dt", "0.001", "--retime"}));
  CHECK_EQUAL(0, retimed.status);
  STRCMP_EQUAL("--dt", last_json(retimed)["dt_source"].get<std::string>().c_str());
  const std::vector<double> t_retimed = test::column(test::read_table(out), 0);
  for (std::size_t n = 0; n < t_retimed.size(); ++n)
    CHECK_EQUAL(static_cast<double>(n) * 0.001, t_retimed[n]);
}

TEST(BusLogs, ReplayOutputLogKeepsEachFramesTimeStampAndInterfaceUnlessRetimed) {
  const std::string log = dir.file("in.log"), out = dir.file("out.csv"), bus = dir.file("bus.log");
  const std::vector<host::LoggedFrame> input = input_log(500, 1700000000000000u, 2000, "can1");
  host::write_candump_log(log, input);
  CHECK_EQUAL(0, run_real(dir, replay_args(log, out, {"--output-log", bus})).status);
  std::size_t inputs = 0;
  std::uint64_t answered_us = 0;
  for (const host::LoggedFrame& entry : host::read_candump_log(bus)) {
    STRCMP_EQUAL("can1", entry.interface.c_str());
    if (entry.frame.id == can::kSeatInput.id) {
      CHECK_EQUAL(input[inputs].time_us, entry.time_us);
      MEMCMP_EQUAL(input[inputs].frame.data, entry.frame.data, 8);
      answered_us = entry.time_us;
      ++inputs;
    } else {
      CHECK_EQUAL(answered_us, entry.time_us);  // an output has the time of what it answers
    }
  }
  LONGS_EQUAL(input.size(), inputs);

  const std::uint64_t before_us = now_us();
  CHECK_EQUAL(
      0, run_real(dir, replay_args(log, out, {"--output-log", bus, "--retime", "--dt", "0.002"}))
             .status);
  const std::vector<host::LoggedFrame> retimed = host::read_candump_log(bus);
  STRCMP_EQUAL("vcan0", retimed[0].interface.c_str());
  CHECK(retimed[0].time_us >= before_us);
  CHECK_EQUAL(retimed[0].time_us + 2000u * 499u, retimed.back().time_us);
}

TEST(BusLogs, AnotherMessageAt1kHzOnTheBusIsCountedApartAndIsNoFault) {
  const std::string log = dir.file("shared.log"), out = dir.file("out.csv"),
                    bus = dir.file("b.log");
  std::vector<host::LoggedFrame> shared;
  for (const host::LoggedFrame& entry : input_log(3000, 1700000000000000u, 1000, "can0")) {
    shared.push_back(entry);
    host::LoggedFrame other = entry;
    other.time_us += 500;
    other.frame.id = 0x321;
    shared.push_back(other);
  }
  host::write_candump_log(log, shared);
  const RealRun run = run_real(dir, replay_args(log, out, {"--output-log", bus}));
  CHECK_EQUAL(0, run.status);
  const nlohmann::json faults = last_json(run)["faults"];
  LONGS_EQUAL(0, faults["faults"].get<int>());
  LONGS_EQUAL(3000, faults["foreign_frames"].get<int>());
  LONGS_EQUAL(3000, faults["accepted"].get<int>());
  // And the fault count the node publishes stays 0.
  for (const host::LoggedFrame& entry : host::read_candump_log(bus)) {
    if (entry.frame.id != can::kSeatScene.id) continue;
    LONGS_EQUAL(0, can::decode_payload(entry.frame.data).words[1]);
  }
}

TEST(BusLogs, NoE2eTakesPlainSensorFramesAndTheStatsSaySo) {
  const std::string log = dir.file("plain.log"), out = dir.file("out.csv");
  std::vector<host::LoggedFrame> plain;
  for (std::uint64_t n = 0; n < 200; ++n) {
    host::LoggedFrame entry{1700000000000000u + 1000u * n, "can0", {}};
    entry.frame.id = can::kSeatInput.id;
    entry.frame.length = 8;
    const std::uint16_t word = can::quantise(can::kSeatInput.signals[0], a_u_of(n)).word;
    entry.frame.data[4] = static_cast<std::uint8_t>(word & 0xFFu);
    entry.frame.data[5] = static_cast<std::uint8_t>(word >> 8);
    plain.push_back(entry);
  }
  host::write_candump_log(log, plain);
  // With the E2E check the frames are refused (no CRC): no samples, one line, status 1.
  const RealRun checked = run_real(dir, replay_args(log, out));
  CHECK_EQUAL(1, checked.status);
  STRCMP_CONTAINS("bad_crc", checked.err.c_str());
  CHECK_FALSE(test::exists(out));
  const RealRun run = run_real(dir, replay_args(log, out, {"--no-e2e"}));
  CHECK_EQUAL(0, run.status);
  const nlohmann::json stats = last_json(run);
  CHECK_FALSE(stats["e2e"].get<bool>());
  LONGS_EQUAL(200, stats["faults"]["accepted"].get<int>());
  LONGS_EQUAL(0, stats["faults"]["faults"].get<int>());
  const std::vector<double> a_u = test::column(test::read_table(out), 1);
  LONGS_EQUAL(200, a_u.size());
  for (std::size_t n = 0; n < a_u.size(); ++n) CHECK_EQUAL(can::quantised_input(a_u_of(n)), a_u[n]);
}

TEST(BusLogs, ReducedOutputsAndTheOutputCycleThinTheNodesFramesNotItsRun) {
  const std::string csv = dir.file("in.csv"), full = dir.file("full.csv"),
                    reduced = dir.file("reduced.csv"), bus = dir.file("bus.log");
  CHECK_EQUAL(0, run_real(dir, {"generate", "--kind", "lorry", "--rms", "1", "--duration", "1",
                                "--dt", "0.001", "--output", csv})
                     .status);
  CHECK_EQUAL(0, run_real(dir, replay_args(csv, full, {"--output-log", bus})).status);
  auto count = frames_by_id(host::read_candump_log(bus));
  LONGS_EQUAL(1001, count[0x180]);
  LONGS_EQUAL(1001, count[0x181]);
  LONGS_EQUAL(101, count[0x182]);
  LONGS_EQUAL(101, count[0x183]);
  const RealRun run = run_real(
      dir, replay_args(csv, reduced,
                       {"--output-log", bus, "--outputs", "reduced", "--output-every", "4"}));
  CHECK_EQUAL(0, run.status);
  count = frames_by_id(host::read_candump_log(bus));
  LONGS_EQUAL(1001, count[0x100]);
  LONGS_EQUAL(251, count[0x180]);  // samples 0, 4, ..., 1000
  LONGS_EQUAL(0, count[0x181]);
  LONGS_EQUAL(101, count[0x182]);
  LONGS_EQUAL(0, count[0x183]);
  STRCMP_EQUAL("reduced", last_json(run)["outputs"].get<std::string>().c_str());
  // The node's run is the same, bit for bit: only what it puts on the bus changes.
  STRCMP_EQUAL(test::read_text(full).c_str(), test::read_text(reduced).c_str());
  CHECK_EQUAL(2, run_real(dir, replay_args(csv, reduced, {"--output-every", "0"})).status);
  CHECK_EQUAL(2, run_real(dir, replay_args(csv, reduced, {"--outputs", "some"})).status);
}

TEST(BusLogs, StatisticsAreNotAvailableUntilTheFirstBlockOfTheWindowCompletes) {
  const std::string csv = dir.file("in.csv"), out = dir.file("out.csv"), bus = dir.file("bus.log");
  CHECK_EQUAL(0, run_real(dir, {"generate", "--kind", "lorry", "--rms", "1", "--duration", "3",
                                "--dt", "0.001", "--output", csv})
                     .status);
  CHECK_EQUAL(0, run_real(dir, replay_args(csv, out, {"--output-log", bus})).status);
  std::size_t not_available = 0, available = 0;
  for (const host::LoggedFrame& entry : host::read_candump_log(bus)) {
    if (entry.frame.id != can::kSeatStats.id) continue;
    const can::Payload p = can::decode_payload(entry.frame.data);
    const double t_ax = can::physical<double>(can::kSeatStats.signals[0], p.words[0]);
    const double p_stick = can::physical<double>(can::kSeatStats.signals[1], p.words[1]);
    // The first 1 s block completes with the 1000th step after sample 0.
    if (p.sample_counter < 1000) {
      CHECK(std::isnan(t_ax) && std::isnan(p_stick));
      LONGS_EQUAL(0xFFFF, p.words[0]);  // all ones, as J1939 says "not available"
      ++not_available;
    } else {
      CHECK(std::isfinite(t_ax) && t_ax > 0.0 && std::isfinite(p_stick));
      ++available;
    }
  }
  LONGS_EQUAL(100, not_available);
  LONGS_EQUAL(201, available);
}

TEST(BusLogs, ExactBusLoadBitsAgreeWithAnIndependentCountOfEveryFrame) {
  const std::string csv = dir.file("in.csv"), out = dir.file("out.csv"), bus = dir.file("bus.log");
  CHECK_EQUAL(0, run_real(dir, {"generate", "--kind", "lorry", "--rms", "1", "--duration", "2",
                                "--dt", "0.001", "--output", csv})
                     .status);
  const RealRun run = run_real(dir, replay_args(csv, out, {"--output-log", bus}));
  CHECK_EQUAL(0, run.status);
  std::vector<host::LoggedFrame> frames = host::read_candump_log(bus);
  // Frames of every kind the formula distinguishes: extended, remote, short.
  host::LoggedFrame extra = frames[0];
  extra.frame.flags = can::kExtendedId;
  extra.frame.id = 0x1ABCDEF0;
  frames.push_back(extra);
  extra.frame.flags = can::kRemote;
  extra.frame.id = 0x7FF;
  extra.frame.length = 2;
  frames.push_back(extra);
  extra.frame.flags = 0;
  extra.frame.id = 0;
  extra.frame.length = 0;
  frames.push_back(extra);
  const std::string all = dir.file("all.log");
  host::write_candump_log(all, frames);
  const std::vector<std::string> oracle = test::split_lines(shell_output(
      dir,
      "/usr/bin/python3 '" STICKSLIP_SOURCE_DIR "/tests/cli/can_frame_bits.py' '" + all + "'"));
  LONGS_EQUAL(frames.size(), oracle.size());
  std::uint64_t exact = 0, worst = 0;
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const unsigned bits = can::frame_bits_exact(frames[n].frame);
    LONGS_EQUAL(std::stoul(oracle[n]), bits);
    CHECK(bits >= can::frame_bits_unstuffed(frames[n].frame));
    CHECK(bits <= can::frame_bits_worst_case(frames[n].frame));
    if (n + 3 < frames.size()) {
      exact += bits;
      worst += can::frame_bits_worst_case(frames[n].frame);
    }
  }
  LONGS_EQUAL(53, can::frame_bits_exact(frames.back().frame));    // 34 zeros: 6 stuff bits
  LONGS_EQUAL(135, can::frame_bits_worst_case(frames[0].frame));  // canbusload: 55 + 10 * 8
  // replay's figures are these bits over the stream's duration.
  const nlohmann::json load = last_json(run)["bus_load"];
  const double duration_s = load["duration_s"].get<double>();
  CHECK_EQUAL(2.001, duration_s);
  CHECK_EQUAL(static_cast<double>(exact) / duration_s, load["bits_per_s_exact"].get<double>());
  CHECK_EQUAL(static_cast<double>(worst) / duration_s, load["bits_per_s_worst_case"].get<double>());
}

TEST(BusLogs, ABadLogIsOneLineNamingFileAndLineWithStatusOneAndNoOutput) {
  const std::string log = dir.file("bad.log"), out = dir.file("out.csv");
  test::write_text(log,
                   "(1700000000.000000) can0 100#3000000095080080\n"
                   "(1700000000.001000) can0 100#90010100\n"
                   "(1700000000.002000) can0 100#ZZ\n");
  const RealRun run = run_real(dir, replay_args(log, out, {"--output-log", dir.file("bus.log")}));
  CHECK_EQUAL(1, run.status);
  LONGS_EQUAL(1, test::split_lines(run.err).size());
  STRCMP_CONTAINS((log + ":3").c_str(), run.err.c_str());
  LONGS_EQUAL(1, dir.entries().size());  // the log alone
}
