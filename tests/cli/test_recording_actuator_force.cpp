// An actuator force column f_a (N) reaches simulate through the recording options too: a logger's
// file read with --signal gives the trace the t,a_u,f_a CSV gives, and a file whose samples are
// resampled (f_a could not stay on its samples) is refused with one line.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::CliRun;
using stickslip::test::read_text;
using stickslip::test::run_stickslip;
using stickslip::test::split_lines;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

constexpr double kPi = 3.14159265358979323846;

double floor_m_per_s2(double t) {
  return 0.9 * std::sin(2.0 * kPi * 1.7 * t);
}
double force_n(double t) {
  return 35.0 * std::sin(2.0 * kPi * 0.6 * t + 0.3);
}

// `step_s` apart, 2 s; the layout as given: "%s,%s,%s" with the header.
void write_recording(const std::string& path, const char* header, const char* separator,
                     double step_s, bool with_force) {
  std::string text = std::string(header) + "\n";
  char row[96];
  const int count = static_cast<int>(std::lround(2.0 / step_s));
  for (int n = 0; n < count; ++n) {
    const double t = n * step_s;
    if (with_force) {
      std::snprintf(row, sizeof row, "%.17g%s%.17g%s%.17g\n", t, separator, floor_m_per_s2(t),
                    separator, force_n(t));
    } else {
      std::snprintf(row, sizeof row, "%.17g%s%.17g\n", t, separator, floor_m_per_s2(t));
    }
    text += row;
  }
  write_text(path, text);
}

}  // namespace

TEST_GROUP(RecordingActuatorForce) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
  CliRun simulate(const std::string& input, const std::string& output,
                  std::vector<std::string> extra) {
    std::vector<std::string> arguments = {"simulate", "--input",    input,   "--output", output,
                                          "--model",  "stick-slip", "--ffk", "40"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_stickslip(arguments);
  }
};

TEST(RecordingActuatorForce, LoggersForceColumnDrivesTheSeatAsTheCsvsDoes) {
  const std::string csv = dir.file("own.csv"), logger = dir.file("logger.txt"),
                    unforced = dir.file("unforced.txt");
  write_recording(csv, "t,a_u,f_a", ",", 0.001, true);
  write_recording(logger, "Time [s];AccZ [m/s^2];f_a [N]", ";", 0.001, true);
  write_recording(unforced, "Time [s];AccZ [m/s^2]", ";", 0.001, false);
  const CliRun own = simulate(csv, dir.file("own.trace.csv"), {});
  LONGS_EQUAL_TEXT(0, own.status, own.err.c_str());
  const CliRun read = simulate(logger, dir.file("logger.trace.csv"), {"--signal", "AccZ"});
  LONGS_EQUAL_TEXT(0, read.status, read.err.c_str());
  const CliRun none = simulate(unforced, dir.file("unforced.trace.csv"), {"--signal", "AccZ"});
  LONGS_EQUAL_TEXT(0, none.status, none.err.c_str());
  const std::string trace = read_text(dir.file("own.trace.csv"));
  LONGS_EQUAL(2001, split_lines(trace).size());
  // The same doubles in, the same force held over each step: the same bytes out.
  CHECK_TRUE(trace == read_text(dir.file("logger.trace.csv")));
  // And the force matters: without it the seat moves otherwise.
  CHECK_FALSE(trace == read_text(dir.file("unforced.trace.csv")));
}

TEST(RecordingActuatorForce, ResampledForceIsRefusedWithOneLine) {
  const std::string logger = dir.file("logger500.txt");
  write_recording(logger, "Time [s];AccZ [m/s^2];f_a [N]", ";", 0.002, true);
  const CliRun run = simulate(logger, dir.file("o.csv"), {"--signal", "AccZ", "--dt", "0.001"});
  LONGS_EQUAL(2, run.status);
  STRCMP_EQUAL(("stickslip: " + logger +
                ": column 'f_a': an actuator force runs on a recording read as it is (one part, "
                "its own step: no gaps held or split, no regridding, no resampling)\n")
                   .c_str(),
               run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("o.csv")));
  // A force in another unit: one line naming it.
  write_recording(logger, "Time [s];AccZ [m/s^2];f_a [kN]", ";", 0.001, true);
  const CliRun unit = simulate(logger, dir.file("o.csv"), {"--signal", "AccZ"});
  LONGS_EQUAL(1, unit.status);
  STRCMP_EQUAL(
      ("stickslip: " + logger + ": column 'f_a' (the actuator force) is in 'kN'; N expected\n")
          .c_str(),
      unit.err.c_str());
}
