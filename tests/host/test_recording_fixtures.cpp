// Recordings made by tools nobody here wrote: tools/make-recording-fixtures.py has python-can
// write one vehicle-style bus (a J1939-style cab-floor acceleration, Motorola, signed, 500 Hz,
// among 1 kHz traffic) as candump, ASC, BLF and TRC logs and has python-can read them back and
// canmatrix decode every signal. Our readers must find the same frames and our DBC reader the
// same values, sample for sample and bit for bit. Times are bit for bit too, except BLF's:
// python-can adds the file's start time (local wall clock) to ns * 1e-9, we report the object time
// / 1e9 since that start, so BLF times are compared as offsets from the first frame within 1 us.
// Says "SKIPPED:" when python3-can or python3-canmatrix is not installed.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"
#include "stickslip/host/io/can_signal.hpp"
#include "stickslip/host/io/dbc.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::CanLog;
using stickslip::host::CanLogFormat;
using stickslip::host::HostError;
using stickslip::test::bit_equal;
using stickslip::test::read_text;
using stickslip::test::split_lines;
namespace host = stickslip::host;

namespace {

// The fixtures, made once per run into the build tree (the test's working directory): their
// directory, "" when the Python tools are missing, "failed" when the script failed. Kept in a
// static buffer: a static std::string made by the first test would count as its memory leak.
const char* fixture_dir() {
  static char dir[4096] = "";
  static bool made = false;
  if (made) return dir;
  made = true;
  const char* pythons[] = {"/usr/bin/python3", "python3"};
  for (const char* python : pythons) {
    const std::string probe = std::string(python) + " -c 'import can, canmatrix' >/dev/null 2>&1";
    if (std::system(probe.c_str()) != 0) continue;
    // In the build tree, wherever the test runs from: never among the sources.
    const std::string out = STICKSLIP_TEST_BINARY_DIR "/recording-fixtures";
    const std::string command = std::string(python) +
                                " " STICKSLIP_SOURCE_DIR "/tools/make-recording-fixtures.py '" +
                                out + "' >'" + out + ".log' 2>&1";
    if (std::system(command.c_str()) != 0) {
      std::printf("\n%s failed:\n%s\n", command.c_str(), read_text(out + ".log").c_str());
      std::snprintf(dir, sizeof dir, "failed");
    } else {
      std::snprintf(dir, sizeof dir, "%s", out.c_str());
    }
    break;
  }
  return dir;
}

bool skipped() {
  if (fixture_dir()[0] != '\0') return false;
  std::printf(
      "\nSKIPPED: python3-can or python3-canmatrix not installed (tools/install-deps.sh installs "
      "them)\n");
  return true;
}

double number(const std::string& text) {
  double value = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  CHECK(result.ec == std::errc() && result.ptr == text.data() + text.size());
  return value;
}

std::string frame_line(const host::LogFrame& frame) {
  char head[32];
  std::snprintf(head, sizeof head, "%X %d %u ", static_cast<unsigned>(frame.id),
                frame.extended ? 1 : 0, static_cast<unsigned>(frame.dlc));
  std::string line = head;
  static const char kHex[] = "0123456789ABCDEF";
  for (std::size_t i = 0; i < frame.length; ++i) {
    line += kHex[frame.data[i] >> 4];
    line += kHex[frame.data[i] & 0x0F];
  }
  return line;
}

struct Expected {
  std::vector<double> t_s;
  std::vector<double> values;
};

void check_against_python(const char* suffix, CanLogFormat format, bool exact_times) {
  if (skipped()) return;
  const std::string dir = fixture_dir();
  CHECK(dir != "failed");
  const std::string path = dir + "/vehicle." + suffix;
  const CanLog log = host::read_can_log(path);
  CHECK(log.format == format);

  const std::vector<std::string> frames =
      split_lines(read_text(dir + "/frames-" + suffix + ".txt"));
  LONGS_EQUAL(frames.size(), log.frames.size());
  for (std::size_t i = 0; i < frames.size() && i < log.frames.size(); ++i)
    STRCMP_EQUAL(frames[i].c_str(), frame_line(log.frames[i]).c_str());

  std::map<std::string, Expected> expected;
  std::vector<std::string> order;
  for (const std::string& line : split_lines(read_text(dir + "/signals-" + suffix + ".txt"))) {
    std::istringstream fields(line);
    std::string name, t, value;
    fields >> name >> t >> value;
    if (expected.find(name) == expected.end()) order.push_back(name);
    expected[name].t_s.push_back(number(t));
    expected[name].values.push_back(number(value));
  }
  LONGS_EQUAL(7, order.size());
  const host::Dbc dbc = host::read_dbc(dir + "/vehicle.dbc");
  for (const std::string& name : order) {
    const host::SignalSeries series = host::extract_signal(log, path, dbc, name);
    const Expected& oracle = expected[name];
    LONGS_EQUAL(oracle.values.size(), series.values.size());
    for (std::size_t i = 0; i < oracle.values.size(); ++i) {
      if (!bit_equal(oracle.values[i], series.values[i])) {
        FAIL((name + " sample " + std::to_string(i) + ": canmatrix " +
              std::to_string(oracle.values[i]) + ", ours " + std::to_string(series.values[i]))
                 .c_str());
      }
      if (exact_times) {
        CHECK(bit_equal(oracle.t_s[i], series.t_s[i]));
      } else {
        const double theirs = oracle.t_s[i] - oracle.t_s[0];
        const double ours = series.t_s[i] - series.t_s[0];
        CHECK(std::fabs(theirs - ours) < 1e-6);
      }
    }
  }
}

}  // namespace

TEST_GROUP(RecordingFixtures){};

TEST(RecordingFixtures, CandumpMatchesPythonCanAndCanmatrix) {
  check_against_python("log", CanLogFormat::kCandump, true);
}

TEST(RecordingFixtures, AscMatchesPythonCanAndCanmatrix) {
  check_against_python("asc", CanLogFormat::kAsc, true);
}

TEST(RecordingFixtures, TrcMatchesPythonCanAndCanmatrix) {
  check_against_python("trc", CanLogFormat::kTrc, true);
}

TEST(RecordingFixtures, BlfMatchesPythonCanAndCanmatrix) {
  check_against_python("blf", CanLogFormat::kBlf, false);
}

TEST(RecordingFixtures, TruncatedPythonBlfIsOneErrorNamingAByteOffset) {
  if (skipped()) return;
  const std::string whole = read_text(std::string(fixture_dir()) + "/vehicle.blf");
  CHECK(whole.size() > 1000);
  for (std::size_t size = 145; size < whole.size(); size += 97) {
    try {
      host::parse_blf(whole.substr(0, size), "cut.blf");
      FAIL(("cut at " + std::to_string(size) + " was accepted").c_str());
    } catch (const HostError& error) {
      const std::string message = error.what();
      CHECK(message.rfind("cut.blf: ", 0) == 0 && message.find('\n') == std::string::npos);
    }
  }
}
