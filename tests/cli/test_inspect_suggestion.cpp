// Recordings as other people's loggers and vehicles write them: `stickslip inspect FILE` (the
// real executable) describes each, and the simulate line it suggests, pasted into a shell as
// printed, runs to the end and writes the trace. One test per shape of file a user brings: a
// logger's export (semicolons, decimal commas, BOM, CRLF, banner lines, extra channels), a file
// with no time column and its rate in the banner, 512 / 500 / 2048 Hz, jittered times, a gap, and
// a vehicle CAN log (candump, ASC, BLF, TRC) with its DBC.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::read_table;
using stickslip::test::read_text;
using stickslip::test::split_lines;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

struct Shell {
  int status;
  std::string out;
};

// Runs `command` by sh in `dir`, the executable's directory first on PATH (as after an install).
Shell shell(const std::string& dir, const std::string& command) {
  const std::string bin = std::filesystem::path(STICKSLIP_EXECUTABLE).parent_path().string();
  const std::string line = "cd '" + dir + "' && PATH='" + bin + "':\"$PATH\" " + command + " 2>&1";
  Shell result{0, ""};
  FILE* pipe = ::popen(line.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// inspect, then its last line, which must be the command; returns that command's output.
std::string inspect_then_simulate(const TempDir& dir, const std::string& file,
                                  const std::string& inspect_flags = "") {
  const Shell inspect = shell(dir.file(""), "stickslip inspect " + file + inspect_flags);
  LONGS_EQUAL_TEXT(0, inspect.status, inspect.out.c_str());
  const std::vector<std::string> lines = split_lines(inspect.out);
  CHECK_TEXT(!lines.empty(), "inspect printed nothing");
  const std::string suggested = lines.back();
  CHECK_TEXT(suggested.rfind("stickslip simulate ", 0) == 0, inspect.out.c_str());
  const Shell run = shell(dir.file(""), suggested);
  LONGS_EQUAL_TEXT(0, run.status, (inspect.out + "\n" + suggested + "\n" + run.out).c_str());
  return inspect.out + run.out;
}

constexpr double kPi = 3.14159265358979323846;
double floor_g(double t) {
  return 0.05 * std::sin(2 * kPi * 2.3 * t) + 0.03 * std::sin(2 * kPi * 7.9 * t + 1.0);
}

std::string comma_decimal(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.6f", value);
  std::string s = text;
  for (char& c : s)
    if (c == '.') c = ',';
  return s;
}

// A logger's export: BOM, banner, comment, `Time [s];AccZ [g];Temp (degC)`, decimal commas,
// CRLF. `jitter` moves every time by up to that fraction of the step; `gap_at` drops 20 samples
// from that index (0: none).
std::string logger_export(double rate_hz, double seconds, double jitter, std::size_t gap_at) {
  std::string text =
      "\xEF\xBB\xBFMSR145 data logger, serial 4711\r\n# exported 2026-11-25\r\n"
      "Time [s];AccZ [g];Temp (degC)\r\n";
  std::uint64_t state = 12345;
  const auto count = static_cast<std::size_t>(seconds * rate_hz);
  for (std::size_t i = 0; i < count; ++i) {
    if (gap_at != 0 && i >= gap_at && i < gap_at + 20) continue;
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double unit = static_cast<double>(state >> 11) * 0x1.0p-53 * 2.0 - 1.0;
    const double t = (static_cast<double>(i) + (i == 0 ? 0.0 : jitter * unit)) / rate_hz;
    text += comma_decimal(t) + ";" + comma_decimal(floor_g(t)) + ";21,5\r\n";
  }
  return text;
}

std::size_t trace_rows(const std::string& path) {
  return read_table(path).rows.size();
}

}  // namespace

TEST_GROUP(InspectSuggestion){};

TEST(InspectSuggestion, LoggerExportAtFiveHundredHertzRunsResampledToOneKilohertz) {
  TempDir dir;
  write_text(dir.file("logger.csv"), logger_export(500, 4, 0, 0));
  const std::string out = inspect_then_simulate(dir, "logger.csv");
  CHECK(out.find("--signal AccZ") != std::string::npos);
  CHECK(out.find("Temp [degC] (not an acceleration)") != std::string::npos);
  LONGS_EQUAL(3999, trace_rows(dir.file("logger.trace.csv")));  // 3.998 s at 1 kHz
}

TEST(InspectSuggestion, LoggerExportsAt512And2048HertzRun) {
  for (double rate : {512.0, 2048.0}) {
    TempDir dir;
    write_text(dir.file("logger.csv"), logger_export(rate, 3, 0, 0));
    const std::string out = inspect_then_simulate(dir, "logger.csv");
    CHECK_TEXT(out.find("resampled to 1000 Hz") != std::string::npos, out.c_str());
  }
}

TEST(InspectSuggestion, JitteredLoggerExportRunsOnAUniformGrid) {
  TempDir dir;
  write_text(dir.file("jittered.csv"), logger_export(500, 4, 0.03, 0));
  const std::string out = inspect_then_simulate(dir, "jittered.csv");
  CHECK_TEXT(out.find("put on a uniform grid (cubic spline)") != std::string::npos, out.c_str());
}

TEST(InspectSuggestion, GappedLoggerExportRunsWithTheGapHeldAndCounted) {
  TempDir dir;
  write_text(dir.file("gapped.csv"), logger_export(500, 4, 0, 1000));
  // Without a policy the gap is refused, named by its time and length, and nothing is written.
  const Shell refused = shell(dir.file(""),
                              "stickslip simulate --input gapped.csv --signal AccZ "
                              "--dt 0.001 --model stick-slip --output x.csv");
  LONGS_EQUAL(1, refused.status);
  CHECK_TEXT(refused.out.find("gapped.csv: gap after t = 1.998 s: 0.042 s without samples") !=
                 std::string::npos,
             refused.out.c_str());
  CHECK(!stickslip::test::exists(dir.file("x.csv")));
  const std::string out = inspect_then_simulate(dir, "gapped.csv");
  CHECK_TEXT(out.find("20 samples held over gaps") != std::string::npos, out.c_str());
}

TEST(InspectSuggestion, NoTimeColumnWithTheRateInTheBannerRuns) {
  TempDir dir;
  std::string text = "Accelerometer export\nSample rate: 512 Hz\nAccZ [m/s^2]\tTemp (degC)\n";
  for (int i = 0; i < 1024; ++i) {
    char row[64];
    std::snprintf(row, sizeof row, "%.6f\t21.5\n", 9.80665 * floor_g(i / 512.0));
    text += row;
  }
  write_text(dir.file("norate.txt"), text);
  const std::string out = inspect_then_simulate(dir, "norate.txt");
  CHECK_TEXT(out.find("--rate 512") != std::string::npos, out.c_str());
}

namespace {

// tools/make-recording-fixtures.py's vehicle bus (python-can wrote it), made once into the build
// tree: its directory, or "" when python3-can or python3-canmatrix is missing.
std::string vehicle_fixtures() {
  static char dir[4096] = "";
  static bool made = false;
  if (made) return dir;
  made = true;
  if (std::system("/usr/bin/python3 -c 'import can, canmatrix' >/dev/null 2>&1") != 0) return dir;
  // In the build tree, wherever the test runs from: never among the sources.
  const std::string out = STICKSLIP_TEST_BINARY_DIR "/recording-fixtures-inspect";
  const std::string command = "/usr/bin/python3 " STICKSLIP_SOURCE_DIR
                              "/tools/make-recording-fixtures.py '" +
                              out + "' >/dev/null 2>&1";
  if (std::system(command.c_str()) == 0) std::snprintf(dir, sizeof dir, "%s", out.c_str());
  return dir;
}

void vehicle_log_runs(const char* extension) {
  const std::string fixtures = vehicle_fixtures();
  if (fixtures.empty()) {
    std::printf("SKIPPED: python3-can or python3-canmatrix missing\n");
    return;
  }
  TempDir dir;
  const std::string log = std::string("vehicle.") + extension;
  std::filesystem::copy_file(fixtures + "/" + log, dir.file(log));
  std::filesystem::copy_file(fixtures + "/vehicle.dbc", dir.file("vehicle.dbc"));
  const std::string out = inspect_then_simulate(dir, log, " --dbc vehicle.dbc");
  CHECK_TEXT(out.find("--signal CabFloor.AccZ") != std::string::npos, out.c_str());
  CHECK_TEXT(out.find("--dt 0.001") != std::string::npos, out.c_str());
  CHECK_TEXT(out.find("resampled to 1000 Hz") != std::string::npos, out.c_str());
  // 2 s of a 500 Hz signal at 1 kHz.
  const std::size_t rows = trace_rows(dir.file("vehicle.trace.csv"));
  CHECK_TEXT(rows >= 1990 && rows <= 2001, std::to_string(rows).c_str());
}

}  // namespace

TEST(InspectSuggestion, VehicleCandumpLogWithItsDbcRuns) {
  vehicle_log_runs("log");
}

TEST(InspectSuggestion, VehicleAscLogWithItsDbcRuns) {
  vehicle_log_runs("asc");
}

TEST(InspectSuggestion, VehicleBlfLogWithItsDbcRuns) {
  vehicle_log_runs("blf");
}

TEST(InspectSuggestion, VehicleTrcLogWithItsDbcRuns) {
  vehicle_log_runs("trc");
}

// simulate reads CabFloor.AccZ at its own 500 Hz step (--dt 0.002, no resampling) to the values
// canmatrix decodes from the same file, times 9.80665, bit for bit.
TEST(InspectSuggestion, SimulateDecodesTheVehicleSignalLikeCanmatrix) {
  const std::string fixtures = vehicle_fixtures();
  if (fixtures.empty()) {
    std::printf("SKIPPED: python3-can or python3-canmatrix missing\n");
    return;
  }
  for (const char* format : {"asc", "trc"}) {
    TempDir dir;
    const Shell run = shell(dir.file(""), "stickslip simulate --input " + fixtures + "/vehicle." +
                                              format + " --dbc " + fixtures +
                                              "/vehicle.dbc --signal CabFloor.AccZ --dt 0.002 "
                                              "--model stick-slip --output out.csv");
    LONGS_EQUAL_TEXT(0, run.status, run.out.c_str());
    std::vector<double> expected;
    for (const std::string& line :
         split_lines(read_text(fixtures + "/signals-" + format + ".txt"))) {
      if (line.rfind("CabFloor.AccZ ", 0) != 0) continue;
      expected.push_back(9.80665 * std::stod(line.substr(line.rfind(' ') + 1)));
    }
    const std::vector<double> a_u = stickslip::test::column(read_table(dir.file("out.csv")), 1);
    LONGS_EQUAL(expected.size(), a_u.size());
    for (std::size_t i = 0; i < a_u.size(); ++i) {
      if (!stickslip::test::bit_equal(expected[i], a_u[i])) {
        FAIL(("sample " + std::to_string(i) + " of " + format).c_str());
      }
    }
  }
}

// A logger at its full scale (+-0.06 g here) writes runs of the same extreme value: inspect and
// simulate count them and say so; the samples are simulated as they are.
TEST(InspectSuggestion, RunsAtFullScaleAreCountedAndSaid) {
  TempDir dir;
  std::string text = "Time [s];AccZ [g]\n";
  std::vector<double> values;
  for (int i = 0; i < 2000; ++i) {
    const double t = i / 500.0;
    double a = floor_g(t);
    if (std::fabs(a) > 0.06) a = a > 0 ? 0.06 : -0.06;
    values.push_back(a);
    text += comma_decimal(t) + ";" + comma_decimal(a) + "\n";
  }
  // Samples in runs of >= 3 at the limits, counted here by their own loop.
  std::size_t clipped = 0;
  for (std::size_t i = 0; i < values.size();) {
    std::size_t end = i;
    while (end < values.size() && values[end] == values[i]) ++end;
    if (end - i >= 3 && std::fabs(values[i]) == 0.06) clipped += end - i;
    i = end;
  }
  CHECK(clipped > 0);
  write_text(dir.file("clipped.csv"), text);
  const std::string out = inspect_then_simulate(dir, "clipped.csv");
  const std::string said = std::to_string(clipped) + " samples in runs at the minimum or maximum";
  CHECK_TEXT(out.find(said) != std::string::npos, out.c_str());
  CHECK_TEXT(out.find("at full scale " + std::to_string(clipped) + " samples") != std::string::npos,
             out.c_str());
}

// A bad file is one line naming the file and its line, exit 1, and no output.
TEST(InspectSuggestion, TimesThatGoBackAreOneLineNamingTheFileLine) {
  TempDir dir;
  write_text(dir.file("back.csv"),
             "Logger\r\nTime [s];AccZ [g]\r\n0;0,1\r\n\r\n0,002;0,2\r\n"
             "0,001;0,3\r\n0,004;0,1\r\n");
  const Shell run = shell(dir.file(""),
                          "stickslip simulate --input back.csv --signal AccZ "
                          "--model stick-slip --output out.csv");
  LONGS_EQUAL(1, run.status);
  STRCMP_EQUAL("stickslip: back.csv:6: t = 0.001 s does not come after 0.002 s\n", run.out.c_str());
  CHECK(!stickslip::test::exists(dir.file("out.csv")));
}
