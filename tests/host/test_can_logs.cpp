// The CAN log readers (sim_host/src/io/{can_log,asc_log,trc_log,blf_log}.cpp) on logs written as
// the formats' own documents and python-can show them: frames, ids, directions, times, what is
// skipped and counted, detection by content, and one-line errors naming file and line or byte.
// tests/host/test_recording_fixtures.cpp checks them against python-can on its own files.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "stickslip/can/codec.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"
#include "stickslip/host/io/can_signal.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/host/io/dbc.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::CanLog;
using stickslip::host::CanLogFormat;
using stickslip::host::detect_can_log_format;
using stickslip::host::HostError;
using stickslip::host::LogFrame;
using stickslip::host::UsageError;
using stickslip::test::bit_equal;
using stickslip::test::TempDir;
using stickslip::test::write_text;
namespace host = stickslip::host;
namespace can = stickslip::can;

namespace {

template <typename Parse>
std::string error_of(Parse parse, const std::string& bytes, const std::string& name) {
  try {
    parse(bytes, name);
  } catch (const HostError& error) {
    return error.what();
  }
  return "(no error)";
}

void check_frame(const LogFrame& frame, double time_s, std::uint32_t id, bool extended,
                 const std::vector<std::uint8_t>& data, char direction) {
  CHECK(bit_equal(time_s, frame.time_s));
  LONGS_EQUAL(id, frame.id);
  CHECK_EQUAL(extended, frame.extended);
  LONGS_EQUAL(data.size(), frame.length);
  for (std::size_t i = 0; i < data.size(); ++i) LONGS_EQUAL(data[i], frame.data[i]);
  CHECK_EQUAL(direction, frame.direction);
}

constexpr const char* kAsc =
    "date Wed Nov 25 01:02:03.000 pm 2026\r\n"
    "base hex  timestamps absolute\r\n"
    "internal events logged\r\n"
    "// version 13.0.0\r\n"
    "Begin Triggerblock Wed Nov 25 01:02:03.000 pm 2026\r\n"
    "   0.000000 Start of measurement\r\n"
    "   0.001000 1  123             Rx   d 8 00 11 22 33 44 55 66 77  Length = 228000 BitCount "
    "= 118 ID = 291\r\n"
    "   0.002000 2  18FEF100x       Tx   d 3 AA BB CC\r\n"
    "   0.003000 1  321             Rx   r\r\n"
    "   0.004000 1  ErrorFrame\r\n"
    "   0.005000 CANFD   1 Rx        456                                   1 0 d 12 00 01 02 03 "
    "04 05 06 07 08 09 0A 0B\r\n"
    "   0.006000 1  Statistic: D 1 R 0 XD 0 XR 0 E 0 O 0 B 0.10%\r\n"
    "   0.007000 1  7FF             Rx   d 0\r\n"
    "End TriggerBlock\r\n";

}  // namespace

TEST_GROUP(AscLog){};

TEST(AscLog, ClassicDataFramesAreReadAndOtherEventsCounted) {
  const CanLog log = host::parse_asc(kAsc, "bus.asc");
  CHECK(log.format == CanLogFormat::kAsc);
  LONGS_EQUAL(3, log.frames.size());
  check_frame(log.frames[0], 0.001, 0x123, false, {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77},
              'R');
  check_frame(log.frames[1], 0.002, 0x18FEF100, true, {0xAA, 0xBB, 0xCC}, 'T');
  STRCMP_EQUAL("2", log.frames[1].channel.c_str());
  check_frame(log.frames[2], 0.007, 0x7FF, false, {}, 'R');
  LONGS_EQUAL(5, log.skipped_events);  // start, remote, error, CAN FD, statistic
}

TEST(AscLog, DecimalBaseAndRelativeTimestamps) {
  const CanLog log = host::parse_asc(
      "date Wed Nov 25 01:02:03 pm 2026\nbase dec  timestamps relative\n"
      "   0.500000 1  291             Rx   d 2 255 16\n"
      "   0.250000 1  291             Rx   d 1 7\n",
      "dec.asc");
  LONGS_EQUAL(2, log.frames.size());
  check_frame(log.frames[0], 0.5, 291, false, {255, 16}, 'R');
  check_frame(log.frames[1], 0.75, 291, false, {7}, 'R');
}

TEST(AscLog, BadDataLineIsNamedByFileAndLine) {
  STRCMP_EQUAL("bus.asc:3: DLC 8 but 2 data bytes",
               error_of(host::parse_asc,
                        "date x\nbase hex timestamps absolute\n"
                        "0.1 1 123 Rx d 8 00 11\n",
                        "bus.asc")
                   .c_str());
  STRCMP_EQUAL("bus.asc:2: CAN id '800' is not a 11-bit hex id",
               error_of(host::parse_asc, "date x\n0.1 1 800 Rx d 1 00\n", "bus.asc").c_str());
  STRCMP_EQUAL("bus.asc:2: data byte 1 'G1' is not a byte",
               error_of(host::parse_asc, "date x\n0.1 1 100 Rx d 1 G1\n", "bus.asc").c_str());
}

// A line shaped as a data frame (direction, then 'd') with a damaged time, channel or direction
// is refused: skipped as an event, it would become a gap that hides the damage.
TEST(AscLog, DataFrameWithADamagedTimeChannelOrDirectionIsRefusedNotSkipped) {
  const std::string head = "date x\nbase hex timestamps absolute\n0.001 1 200 Rx d 1 00\n";
  STRCMP_EQUAL("bus.asc:4: time '0.01x000' is not seconds (a decimal >= 0)",
               error_of(host::parse_asc, head + "0.01x000 1 200 Rx d 1 00\n", "bus.asc").c_str());
  STRCMP_EQUAL("bus.asc:4: time '-0.100000' is not seconds (a decimal >= 0)",
               error_of(host::parse_asc, head + "-0.100000 1 200 Rx d 1 00\n", "bus.asc").c_str());
  STRCMP_EQUAL("bus.asc:4: channel 'X' is not a number",
               error_of(host::parse_asc, head + "0.002 X 200 Rx d 1 00\n", "bus.asc").c_str());
  STRCMP_EQUAL("bus.asc:4: data frame without its direction (Rx or Tx) before 'd'",
               error_of(host::parse_asc, head + "0.002 1 200 d 1 00\n", "bus.asc").c_str());
  // The direction's case is not the frame's content: 'rx' is a received frame.
  const CanLog log = host::parse_asc(head + "0.002 1 200 rx d 1 05\n", "bus.asc");
  LONGS_EQUAL(2, log.frames.size());
  check_frame(log.frames[1], 0.002, 0x200, false, {0x05}, 'R');
  LONGS_EQUAL(0, log.skipped_events);
}

TEST_GROUP(TrcLog){};

TEST(TrcLog, Version11LinesAsPeakDocumentsThem) {
  const CanLog log = host::parse_trc(
      ";$FILEVERSION=1.1\n"
      ";$STARTTIME=43474.5671666667\n"
      ";   Message Number\n"
      ";---+--   ----+----  --+--  ----+---  +  -+ -- -- -- -- -- -- --\n"
      "     1)      1059.9  Rx         0300  8  00 00 00 00 04 00 00 00 \n"
      "     2)      1283.2  Tx     18EFC0F1  3  01 02 03\n"
      "     3)      1298.9  Error      0000  8  00 00 00 00 00 00 00 00\n"
      "     4)      1300.0  Rx         0301  4  RTR\n",
      "peak.trc");
  LONGS_EQUAL(2, log.frames.size());
  check_frame(log.frames[0], 1059.9 / 1000.0, 0x300, false, {0, 0, 0, 0, 4, 0, 0, 0}, 'R');
  check_frame(log.frames[1], 1283.2 / 1000.0, 0x18EFC0F1, true, {1, 2, 3}, 'T');
  LONGS_EQUAL(2, log.skipped_events);
}

TEST(TrcLog, Version2ColumnsAsDeclared) {
  const CanLog log = host::parse_trc(
      ";$FILEVERSION=2.1\r\n"
      ";$STARTTIME=46351.5004\r\n"
      ";$COLUMNS=N,O,T,B,I,d,R,L,D\r\n"
      "      1         1.000 DT  1     0123 Rx -  8    00 11 22 33 44 55 66 77\r\n"
      "      2         2.500 DT  2  CFF1231 Tx -  2    AB CD\r\n"
      "      3         3.000 ST  1          Rx    4    00 00 00 08\r\n"
      "      4         4.000 RR  1     0123 Rx -  2\r\n",
      "v21.trc");
  LONGS_EQUAL(2, log.frames.size());
  check_frame(log.frames[0], 0.001, 0x123, false, {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77},
              'R');
  check_frame(log.frames[1], 0.0025, 0xCFF1231, true, {0xAB, 0xCD}, 'T');
  STRCMP_EQUAL("2", log.frames[1].channel.c_str());
  LONGS_EQUAL(2, log.skipped_events);
  // 2.0 without ;$COLUMNS: N,O,T,I,d,l,D.
  const CanLog v20 = host::parse_trc(
      ";$FILEVERSION=2.0\n      1      10.000 DT     0456 Rx 2  AA BB\n", "v20.trc");
  LONGS_EQUAL(1, v20.frames.size());
  check_frame(v20.frames[0], 0.01, 0x456, false, {0xAA, 0xBB}, 'R');
}

TEST(TrcLog, BadLineIsNamedByFileAndLine) {
  STRCMP_EQUAL(
      "v.trc:2: data byte 2 'XY' is not a hex byte",
      error_of(host::parse_trc, ";$FILEVERSION=1.1\n 1) 1.0 Rx 0100 2 00 XY\n", "v.trc").c_str());
  STRCMP_EQUAL("v.trc:1: TRC file version '3.0' is not 1.0..1.3, 2.0 or 2.1",
               error_of(host::parse_trc, ";$FILEVERSION=3.0\n", "v.trc").c_str());
}

TEST_GROUP(CandumpRecording){};

TEST(CandumpRecording, CrlfLinesDirectionsAndSkippedKinds) {
  const CanLog log = host::parse_candump_text(
      "(1700000000.000200) can0 0CF004FE#0019000019000000 R\r\n"
      "(1700000000.000400) can0 123#DEADBEEF T\r\n"
      "\r\n"
      "(1700000000.000500) can0 321#R\r\n"
      "(1700000000.000600) can0 20000080#0000000000000000\r\n"
      "(1700000000.000700) can0 456##1000102030405060708090A0B\r\n"
      "(1700000000.000800) vcan1 7FF#\r\n",
      "bus.log");
  LONGS_EQUAL(3, log.frames.size());
  check_frame(log.frames[0], 1700000000.0002, 0x0CF004FE, true, {0, 0x19, 0, 0, 0x19, 0, 0, 0},
              'R');
  check_frame(log.frames[1], 1700000000.0004, 0x123, false, {0xDE, 0xAD, 0xBE, 0xEF}, 'T');
  check_frame(log.frames[2], 1700000000.0008, 0x7FF, false, {}, 0);
  STRCMP_EQUAL("vcan1", log.frames[2].channel.c_str());
  LONGS_EQUAL(3, log.skipped_events);
}

TEST(CandumpRecording, BadRecordIsNamedByFileAndLine) {
  STRCMP_EQUAL("bus.log:2: data must be hex byte pairs",
               error_of(host::parse_candump_text,
                        "(1.000000) can0 123#00\r\n(1.000001) can0 123#0G\r\n", "bus.log")
                   .c_str());
}

TEST_GROUP(BlfLog){};

namespace {

void put16(std::string& out, std::uint16_t v) {
  out += static_cast<char>(v & 0xFF);
  out += static_cast<char>(v >> 8);
}
void put32(std::string& out, std::uint32_t v) {
  put16(out, static_cast<std::uint16_t>(v & 0xFFFF));
  put16(out, static_cast<std::uint16_t>(v >> 16));
}
void put64(std::string& out, std::uint64_t v) {
  put32(out, static_cast<std::uint32_t>(v & 0xFFFFFFFFu));
  put32(out, static_cast<std::uint32_t>(v >> 32));
}

// An object as python-can's blf.py lays it out (OBJ_HEADER_BASE_STRUCT "<4sHHLL" and
// OBJ_HEADER_V1_STRUCT "<LHHQ"), followed by its padding to 4 bytes.
std::string object_v1(std::uint32_t type, std::uint32_t time_flags, std::uint64_t timestamp,
                      const std::string& body) {
  std::string out = "LOBJ";
  put16(out, 32);
  put16(out, 1);
  put32(out, static_cast<std::uint32_t>(32 + body.size()));
  put32(out, type);
  put32(out, time_flags);
  put16(out, 0);
  put16(out, 0);
  put64(out, timestamp);
  out += body;
  out.append(body.size() % 4, '\0');
  return out;
}

// CAN_MSG_STRUCT "<HBBL8s".
std::string can_message(std::uint16_t channel, std::uint8_t flags, std::uint8_t dlc,
                        std::uint32_t id, const std::string& data8) {
  std::string out;
  put16(out, channel);
  out += static_cast<char>(flags);
  out += static_cast<char>(dlc);
  put32(out, id);
  out += data8;
  return out;
}

// A file of one stored (uncompressed) log container holding `inner`; `start` is the header's
// start time (SYSTEMTIME: year, month, day of week, day, hour, minute, second, ms), zero if empty.
std::string blf_file(const std::string& inner, const std::vector<std::uint16_t>& start = {}) {
  std::string out = "LOGG";
  put32(out, 144);
  out.resize(40, '\0');
  for (const std::uint16_t field : start) put16(out, field);
  out.resize(144, '\0');
  std::string container;
  put16(container, 0);  // stored
  container.append(6, '\0');
  put32(container, static_cast<std::uint32_t>(inner.size()));
  container.append(4, '\0');
  container += inner;
  std::string object = "LOBJ";
  put16(object, 16);
  put16(object, 1);
  put32(object, static_cast<std::uint32_t>(16 + container.size()));
  put32(object, 10);
  out += object + container;
  out.append(container.size() % 4, '\0');
  return out;
}

std::string sample_blf() {
  const std::string inner =
      object_v1(1, 2, 1500000000u,
                can_message(1, 0, 8, 0x123, "\x01\x02\x03\x04\x05\x06\x07\x08")) +
      object_v1(73, 2, 1600000000u, std::string(36, '\0')) +  // CAN_ERROR_EXT: skipped
      object_v1(86, 1, 250u,
                can_message(2, 1, 3, 0x80000000u | 0x18FEF100u,
                            std::string("\xAA\xBB\xCC\0\0\0\0\0", 8)) +
                    std::string(8, '\0')) +  // CAN_MESSAGE2's extra fields
      object_v1(1, 2, 1700000000u, can_message(1, 0x80, 2, 0x321, std::string(8, '\0')));
  return blf_file(inner);
}

}  // namespace

TEST(BlfLog, CanMessagesOfStoredContainersAndTheirTimestampUnits) {
  const CanLog log = host::parse_blf(sample_blf(), "bus.blf");
  LONGS_EQUAL(2, log.frames.size());
  check_frame(log.frames[0], 1.5, 0x123, false, {1, 2, 3, 4, 5, 6, 7, 8}, 'R');
  STRCMP_EQUAL("1", log.frames[0].channel.c_str());
  check_frame(log.frames[1], 250 / 1e5, 0x18FEF100, true, {0xAA, 0xBB, 0xCC}, 'T');
  LONGS_EQUAL(2, log.skipped_events);  // the error frame and the remote request
}

TEST(BlfLog, EveryTruncationIsOneErrorNamingAByteOffset) {
  const std::string whole = sample_blf();
  for (std::size_t size = 0; size < whole.size(); ++size) {
    const std::string message = error_of(host::parse_blf, whole.substr(0, size), "bus.blf");
    if (size == 144) {  // the header alone: a log of no objects
      STRCMP_EQUAL("(no error)", message.c_str());
      continue;
    }
    if (message.rfind("bus.blf: byte ", 0) != 0 && message.rfind("bus.blf: log ", 0) != 0)
      FAIL(("cut at " + std::to_string(size) + ": " + message).c_str());
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST(BlfLog, WrongSignatureAndContainerSizesAreRefused) {
  STRCMP_EQUAL("x.blf: byte 0: not a BLF file (a 144-byte header starting 'LOGG' expected)",
               error_of(host::parse_blf, std::string(200, 'x'), "x.blf").c_str());
  std::string corrupt = sample_blf();
  corrupt[144 + 11] = '\x7F';  // the container's size, most significant byte
  const std::string message = error_of(host::parse_blf, corrupt, "x.blf");
  CHECK(message.rfind("x.blf: byte 144: object size 21307", 0) == 0);
  CHECK(message.find(" runs beyond the file (") != std::string::npos);
}

TEST_GROUP(CanLogDetection){};

TEST(CanLogDetection, ContentDecidesOverTheExtension) {
  CHECK(detect_can_log_format(kAsc, "looks-like.log") == CanLogFormat::kAsc);
  CHECK(detect_can_log_format(sample_blf(), "data.bin") == CanLogFormat::kBlf);
  CHECK(detect_can_log_format(";$FILEVERSION=1.1\n", "peak.asc") == CanLogFormat::kTrc);
  CHECK(detect_can_log_format("(1.000000) can0 123#00\n", "dump.txt") == CanLogFormat::kCandump);
  CHECK(detect_can_log_format("\n", "bus.trc") == CanLogFormat::kTrc);
  try {
    detect_can_log_format("hello\n", "notes.txt");
    FAIL("expected a HostError");
  } catch (const HostError& error) {
    CHECK(std::string(error.what()).rfind("notes.txt: not a CAN log this tool reads", 0) == 0);
  }
}

TEST(CanLogDetection, ReadCanLogDispatchesOnContent) {
  TempDir dir;
  CHECK(dir.ok());
  const std::string path = dir.file("recording.dat");
  write_text(path, sample_blf());
  const CanLog log = host::read_can_log(path);
  CHECK(log.format == CanLogFormat::kBlf);
  LONGS_EQUAL(2, log.frames.size());
}

TEST_GROUP(CanSignal){};

TEST(CanSignal, SeatInputOfAProjectLogDecodesToTheCodecSamples) {
  TempDir dir;
  CHECK(dir.ok());
  // The project's own writer and codec make the log; other traffic is interleaved.
  std::vector<host::LoggedFrame> frames;
  std::vector<double> expected;
  for (int n = 0; n < 300; ++n) {
    host::LoggedFrame input;
    input.time_us = 1700000000000000u + static_cast<std::uint64_t>(n) * 1000u;
    input.interface = "can0";
    const double a_u = 9.0 * std::sin(0.05 * n);
    input.frame = can::make_input_frame(a_u, static_cast<std::uint64_t>(n));
    frames.push_back(input);
    expected.push_back(can::quantised_input(a_u));
    host::LoggedFrame other = input;
    other.time_us += 300;
    other.frame.id = 0x181;
    frames.push_back(other);
  }
  const std::string path = dir.file("seat.log");
  host::write_candump_log(path, frames);
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const host::SignalSeries series =
      host::extract_signal(host::read_can_log(path), path, dbc, "SeatInput.a_u");
  STRCMP_EQUAL("m/s^2", series.unit.c_str());
  LONGS_EQUAL(expected.size(), series.values.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(bit_equal(expected[i], series.values[i]));
    CHECK(bit_equal(1700000000.0 + 0.001 * static_cast<double>(i), series.t_s[i]) ||
          std::fabs(series.t_s[i] - (1700000000.0 + 0.001 * static_cast<double>(i))) < 1e-6);
  }
}

TEST(CanSignal, UnknownNamesAndAbsentMessagesAreOneLine) {
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const CanLog log = host::parse_candump_text("(1.000000) can0 123#00\n", "bus.log");
  const auto error = [&](const char* selector) {
    try {
      host::extract_signal(log, "bus.log", dbc, selector);
    } catch (const HostError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error("SeatInput.a_x").find("message 'SeatInput' has no signal 'a_x' (its signals: ") !=
        std::string::npos);
  CHECK(error("Nope.a_u").find("no message 'Nope' (the messages: SeatInput, ") !=
        std::string::npos);
  STRCMP_EQUAL("bus.log: no frame of message 'SeatInput' (id 0x100) among its 1 data frames",
               error("SeatInput.a_u").c_str());
  CHECK(error("a_u").find("expected MESSAGE.SIGNAL") != std::string::npos);
}

// Every decoded sample knows its frame, so a message about a sample (times that go backwards,
// tests/cli) names it: the line in a text log, the place among the data frames in a BLF file.
TEST(CanSignal, EachSampleNamesItsFrameByLineInTextAndByPlaceInBlf) {
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const std::string asc =
      "date Fri Nov 27 05:00:00.000 am 2026\n"
      "base hex  timestamps absolute\n"
      "   0.001000 1  100             Rx   d 8 00 00 00 00 00 00 00 00\n"
      "   0.001500 1  181             Rx   d 2 00 00\n"
      "   0.002000 1  100             Rx   d 8 01 00 00 00 00 00 00 00\n";
  const host::SignalSeries text_series =
      host::extract_signal(host::parse_asc(asc, "bus.asc"), "bus.asc", dbc, "SeatInput.a_u");
  CHECK(text_series.frame_lines);
  LONGS_EQUAL(2, text_series.frames.size());
  LONGS_EQUAL(3, text_series.frames[0]);
  LONGS_EQUAL(5, text_series.frames[1]);

  const std::string inner =
      object_v1(1, 2, 1000000u, can_message(1, 0, 2, 0x181, std::string(8, '\0'))) +
      object_v1(73, 2, 1100000u, std::string(36, '\0')) +  // an error frame: not a data frame
      object_v1(1, 2, 2000000u, can_message(1, 0, 8, 0x100, std::string(8, '\0')));
  const host::SignalSeries blf_series = host::extract_signal(
      host::parse_blf(blf_file(inner), "bus.blf"), "bus.blf", dbc, "SeatInput.a_u");
  CHECK(!blf_series.frame_lines);
  LONGS_EQUAL(1, blf_series.frames.size());
  LONGS_EQUAL(2, blf_series.frames[0]);
}

TEST_GROUP(CanLogChannels){};

namespace {

// SeatInput (0x100) on can0 and can1 with other values of a_u (bytes 4-5), 1 kHz each, as candump
// -l writes two buses into one log.
std::string two_bus_candump() {
  std::string text;
  char line[96];
  for (int n = 0; n < 20; ++n) {
    for (const char* bus : {"can0", "can1"}) {
      const int value = bus[3] == '0' ? n : 100 + n;
      std::snprintf(line, sizeof line, "(1700000000.%06d) %s 100#00000000%02X000000\n", n * 1000,
                    bus, value);
      text += line;
    }
  }
  return text;
}

std::string usage_error(const CanLog& log, const host::Dbc& dbc, const char* channel) {
  try {
    host::extract_signal(log, "bus.log", dbc, "SeatInput.a_u", channel);
  } catch (const UsageError& error) {
    return error.what();
  }
  return "(no error)";
}

}  // namespace

TEST(CanLogChannels, ChannelKeepsTheFramesOfThatBusOnly) {
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const CanLog log = host::parse_candump_text(two_bus_candump(), "bus.log");
  const std::vector<std::string> channels = host::log_channels(log);
  LONGS_EQUAL(2, channels.size());
  STRCMP_EQUAL("can0", channels[0].c_str());
  STRCMP_EQUAL("can1", channels[1].c_str());
  const host::SignalSeries can0 =
      host::extract_signal(log, "bus.log", dbc, "SeatInput.a_u", "can0");
  const host::SignalSeries can1 =
      host::extract_signal(log, "bus.log", dbc, "SeatInput.a_u", "can1");
  LONGS_EQUAL(20, can0.values.size());
  LONGS_EQUAL(20, can1.values.size());
  for (std::size_t i = 0; i < 20; ++i) {
    CHECK(bit_equal(1700000000.0 + 0.001 * static_cast<double>(i), can0.t_s[i]) ||
          std::fabs(can0.t_s[i] - (1700000000.0 + 0.001 * static_cast<double>(i))) < 1e-6);
    CHECK(can0.values[i] != can1.values[i]);  // the buses' own payloads, not merged
  }
}

TEST(CanLogChannels, AChannelTheLogDoesNotHaveIsRefusedNamingItsChannels) {
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const CanLog log = host::parse_candump_text(two_bus_candump(), "bus.log");
  STRCMP_EQUAL("--channel can2: bus.log has no frame on that channel (its channels: can0, can1)",
               usage_error(log, dbc, "can2").c_str());
}

// Two buses' frames in one stream would alternate between two signals: refused unless one is
// picked; a log of one bus needs no --channel.
TEST(CanLogChannels, AMessageOnTwoChannelsIsRefusedUntilOneIsPicked) {
  const host::Dbc dbc =
      host::read_dbc(std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc");
  const CanLog log = host::parse_candump_text(two_bus_candump(), "bus.log");
  STRCMP_EQUAL(
      "bus.log: message 'SeatInput' is on channels can0, can1; pick one bus with --channel NAME",
      usage_error(log, dbc, "").c_str());
  const CanLog one_bus = host::parse_candump_text(
      "(1.000000) can1 100#0100000000000000\n(1.001000) can1 100#0200000000000000\n", "bus.log");
  LONGS_EQUAL(2, host::extract_signal(one_bus, "bus.log", dbc, "SeatInput.a_u").values.size());
}

TEST_GROUP(CanLogTiming) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

namespace {

// 1 s of SeatInput at 2 kHz as python-can's BLFWriter writes it from a clock since the epoch:
// each object's timestamp is int((t - t_first) * 1e9) ns, t = 1.7e9 s + n / 2000 (moved by
// `jitter` / 2 of the step, alternating in sign: steps `jitter` off), in doubles as Python computes
// them; the header's start time is 2023-11-14 22:13:20.
std::string epoch_clock_blf(double jitter) {
  std::string inner;
  const double t_first = 1.7e9;
  for (int n = 0; n < 2000; ++n) {
    const double wobble = n == 0 ? 0.0 : (n % 2 == 0 ? jitter : -jitter) / 2.0 / 2000.0;
    const double t = 1.7e9 + n / 2000.0 + wobble;
    const auto stamp = static_cast<std::uint64_t>((t - t_first) * 1e9);
    const can::Frame frame =
        can::make_input_frame(std::sin(0.01 * n), static_cast<std::uint64_t>(n));
    inner += object_v1(1, 2, stamp,
                       can_message(1, 0, frame.length, frame.id,
                                   std::string(reinterpret_cast<const char*>(frame.data), 8)));
  }
  return blf_file(inner, {2023, 11, 2, 14, 22, 13, 20, 0});
}

host::RecordingOptions seat_input_options() {
  host::RecordingOptions options;
  options.dbc = std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc";
  options.signal = "SeatInput.a_u";
  return options;
}

}  // namespace

// The steps of such a log are 2097 or 2098 spacings of a double at 1.7e9 s (2.4e-7 s): 4.8e-4
// of the step, which is rounding, not the bus's timing.
TEST(CanLogTiming, A2kHzBlfTakenFromAClockSinceTheEpochIsUniform) {
  const std::string path = dir.file("epoch.blf");
  write_text(path, epoch_clock_blf(0.0));
  const CanLog log = host::read_can_log(path);
  DOUBLES_EQUAL(1.7e9, log.start_time_epoch_s, 1e-3);
  host::LoadedRecording loaded;
  try {
    loaded = host::read_recording(path, seat_input_options());
  } catch (const host::HostError& error) {
    FAIL(error.what());  // taken for jitter: "give --dt S"
  }
  LONGS_EQUAL(1, loaded.segments.size());
  LONGS_EQUAL(2000, loaded.segments.front().a_u_m_per_s2.size());
  LONGS_EQUAL(0, loaded.report.regridded_samples);
  CHECK(loaded.report.jitter_max > 1e-4);  // the rounding is there, and tolerated
  DOUBLES_EQUAL(2000.0, loaded.report.source_rate_hz, 0.01);
}

TEST(CanLogTiming, FivePercentJitterInAnEpochClockBlfIsStillJitter) {
  const std::string path = dir.file("jitter.blf");
  write_text(path, epoch_clock_blf(0.05));
  try {
    host::read_recording(path, seat_input_options());
    FAIL("expected a HostError");
  } catch (const HostError& error) {
    STRCMP_CONTAINS(": the sample times jitter by up to ", error.what());
    STRCMP_CONTAINS("give --dt S", error.what());
  }
}
