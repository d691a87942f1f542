// A recording at another rate, with jittered times, put on the model's step
// (run/recording_source.hpp): one continuous band-limited signal - a sum of sines below 100 Hz -
// sampled twice, at 500 Hz with every instant moved by up to +-3 % of the step, and at 1 kHz on
// the exact grid. The first, read with --dt 0.001 (cubic spline onto the 500 Hz grid, then
// libsoxr to 1 kHz), must give the second's T_ax within 0.1 % and p within 0.005.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/can/codec.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/host/io/csv_reader.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::column;
using stickslip::test::read_table;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;
using stickslip::test::write_text;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Amplitudes falling with frequency, as a vehicle floor's do; the highest line at 97.1 Hz.
struct Line {
  double amplitude_m_per_s2, frequency_hz, phase;
};
constexpr Line kLines[] = {{0.8, 1.3, 0.1},   {0.6, 2.9, 1.7},   {0.5, 4.7, 2.2},
                           {0.35, 8.3, 0.6},  {0.25, 13.1, 4.0}, {0.15, 21.7, 3.1},
                           {0.08, 37.9, 5.2}, {0.04, 61.3, 0.9}, {0.02, 97.1, 2.6}};

double floor_signal(double t_s) {
  double sum = 0.0;
  for (const Line& line : kLines)
    sum += line.amplitude_m_per_s2 * std::sin(2.0 * kPi * line.frequency_hz * t_s + line.phase);
  return sum;
}

// The spline's error bound for this signal: (5/384) h^4 max|f''''|, h the longest step.
double spline_error_bound(double h_s) {
  double fourth = 0.0;
  for (const Line& line : kLines)
    fourth += line.amplitude_m_per_s2 * std::pow(2.0 * kPi * line.frequency_hz, 4.0);
  return 5.0 / 384.0 * std::pow(h_s, 4.0) * fourth;
}

std::string csv_row(double t, double a) {
  char row[64];
  std::snprintf(row, sizeof row, "%.17g,%.17g\n", t, a);
  return row;
}

constexpr double kDurationS = 60.0;

// Writes the jittered 500 Hz file; returns its longest step.
double write_jittered(const std::string& path) {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // a fixed LCG: the same file on every machine
  std::string text = "t,a_u\n";
  double previous = 0.0, longest = 0.0;
  const auto count = static_cast<std::size_t>(kDurationS * 500.0) + 1;
  for (std::size_t i = 0; i < count; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const double unit = static_cast<double>(state >> 11) * 0x1.0p-53 * 2.0 - 1.0;  // [-1, 1)
    const double t = i == 0 ? 0.0 : static_cast<double>(i) * 0.002 + unit * 0.03 * 0.002;
    if (i > 0) longest = std::max(longest, t - previous);
    previous = t;
    text += csv_row(t, floor_signal(t));
  }
  write_text(path, text);
  return longest;
}

void write_truth(const std::string& path) {
  std::string text = "t,a_u\n";
  const auto count = static_cast<std::size_t>(kDurationS * 1000.0) + 1;
  for (std::size_t i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) * 0.001;
    text += csv_row(t, floor_signal(t));
  }
  write_text(path, text);
}

nlohmann::json stats_of(const stickslip::test::CliRun& run) {
  const std::vector<std::string> lines = stickslip::test::split_lines(run.out);
  return nlohmann::json::parse(lines.empty() ? std::string("null") : lines.back());
}

}  // namespace

TEST_GROUP(RecordingResampling){};

TEST(RecordingResampling, JitteredFiveHundredHertzOnTheKilohertzStepGivesTheSameTaxAndP) {
  TempDir dir;
  const double longest_step = write_jittered(dir.file("jittered.csv"));
  write_truth(dir.file("truth.csv"));
  const std::vector<std::string> model = {"--model", "stick-slip", "--ffk", "60"};
  std::vector<std::string> jittered = {
      "simulate", "--input", dir.file("jittered.csv"), "--output", dir.file("j.out.csv"),
      "--dt",     "0.001"};
  std::vector<std::string> truth = {"simulate", "--input", dir.file("truth.csv"), "--output",
                                    dir.file("t.out.csv")};
  jittered.insert(jittered.end(), model.begin(), model.end());
  truth.insert(truth.end(), model.begin(), model.end());
  const auto j = run_stickslip(jittered);
  const auto t = run_stickslip(truth);
  LONGS_EQUAL_TEXT(0, j.status, j.err.c_str());
  LONGS_EQUAL_TEXT(0, t.status, t.err.c_str());
  const nlohmann::json js = stats_of(j), ts = stats_of(t);
  // The act is reported: samples regridded and the rate changed.
  CHECK(js["recording"]["regridded_samples"].get<std::size_t>() > 0);
  CHECK(js["recording"]["resampled"].get<bool>());
  CHECK(j.err.find("resampled to 1000 Hz") != std::string::npos);

  const double tax_j = js["T_ax"], tax_t = ts["T_ax"], p_j = js["p_stick"], p_t = ts["p_stick"];
  std::printf("\n  T_ax %.6f vs %.6f (%.4f %%), p %.5f vs %.5f\n", tax_j, tax_t,
              100.0 * (tax_j - tax_t) / tax_t, p_j, p_t);
  CHECK(p_t > 0.05 && p_t < 0.95);  // a run where sticking matters
  CHECK(std::fabs(tax_j - tax_t) <= 1e-3 * tax_t);
  CHECK(std::fabs(p_j - p_t) <= 0.005);

  // Sample by sample, away from the ends (where the resampling filter sees the file start), the
  // a_u the model got is the continuous signal within the spline's bound (libsoxr VHQ adds
  // nothing measurable at this scale: its pass band is flat to 0.95 of 250 Hz).
  const auto table = read_table(dir.file("j.out.csv"));
  const std::vector<double> times = column(table, 0), a_u = column(table, 1);
  double worst = 0.0;
  for (std::size_t n = 0; n < times.size(); ++n) {
    if (times[n] < 0.1 || times[n] > kDurationS - 0.1) continue;
    worst = std::max(worst, std::fabs(a_u[n] - floor_signal(times[n])));
  }
  const double bound = spline_error_bound(longest_step);
  std::printf("  a_u max error %.3g m/s^2 (bound %.3g)\n", worst, bound);
  CHECK(worst <= bound);
}

// --gaps split: each part is its own run; the whole is the parts' RMS values weighted by samples
// (checked here against the two parts' own figures) and the gap is counted.
TEST(RecordingResampling, SplitRunsEachPartAloneAndReportsEachAndTheWhole) {
  TempDir dir;
  std::string text = "t,a_u\n";
  for (int i = 0; i < 4000; ++i) {
    if (i >= 2000 && i < 2100) continue;  // the logger lost 0.1 s
    const double t = i * 0.001;
    text += csv_row(t, floor_signal(t));
  }
  write_text(dir.file("gapped.csv"), text);
  const auto run =
      run_stickslip({"simulate", "--input", dir.file("gapped.csv"), "--output", dir.file("out.csv"),
                     "--gaps", "split", "--model", "stick-slip", "--ffk", "60"});
  LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
  const nlohmann::json stats = stats_of(run);
  LONGS_EQUAL(1, stats["recording"]["gaps"].get<int>());
  LONGS_EQUAL(2, stats["recording"]["segments"].get<int>());
  const nlohmann::json& parts = stats["segments"];
  LONGS_EQUAL(2, parts.size());
  LONGS_EQUAL(2000, parts[0]["samples"].get<int>());
  LONGS_EQUAL(1900, parts[1]["samples"].get<int>());
  DOUBLES_EQUAL(2.1, parts[1]["t_start_s"].get<double>(), 1e-12);
  LONGS_EQUAL(3900, stats["samples"].get<int>());
  LONGS_EQUAL(3900, read_table(dir.file("out.csv")).rows.size());  // both parts, one header
  CHECK(run.err.find("split into 2 segments") != std::string::npos);

  // Ride comfort of the whole from the parts, each run here as a file of its own: weighted mean
  // squares added by samples, VDV by fourth powers, MTVV the larger. The same doubles go through
  // the same arithmetic in another order, so only rounding separates them.
  std::string first = "t,a_u\n", second = "t,a_u\n";
  for (int i = 0; i < 4000; ++i) {
    if (i >= 2000 && i < 2100) continue;
    const double t = i * 0.001;
    (i < 2000 ? first : second) += csv_row(t, floor_signal(t));
  }
  write_text(dir.file("first.csv"), first);
  write_text(dir.file("second.csv"), second);
  std::vector<nlohmann::json> alone;
  for (const char* name : {"first.csv", "second.csv"}) {
    const auto part = run_stickslip({"simulate", "--input", dir.file(name), "--output",
                                     dir.file("part.csv"), "--model", "stick-slip", "--ffk", "60"});
    LONGS_EQUAL_TEXT(0, part.status, part.err.c_str());
    alone.push_back(stats_of(part));
  }
  const auto mean_square = [&](const char* key) {
    double sum = 0.0;
    for (const nlohmann::json& part : alone) {
      const double rms = part[key].get<double>();
      sum += part["samples"].get<double>() * rms * rms;
    }
    return std::sqrt(sum / (alone[0]["samples"].get<double>() + alone[1]["samples"].get<double>()));
  };
  const double seat = mean_square("seat_weighted_rms"), floor = mean_square("floor_weighted_rms");
  DOUBLES_EQUAL(seat, stats["seat_weighted_rms"].get<double>(), 1e-14 * seat);
  DOUBLES_EQUAL(floor, stats["floor_weighted_rms"].get<double>(), 1e-14 * floor);
  DOUBLES_EQUAL(seat / floor, stats["seat"].get<double>(), 1e-14 * seat / floor);
  const double vdv = std::pow(
      std::pow(alone[0]["vdv"].get<double>(), 4.0) + std::pow(alone[1]["vdv"].get<double>(), 4.0),
      0.25);
  DOUBLES_EQUAL(vdv, stats["vdv"].get<double>(), 1e-14 * vdv);
  DOUBLES_EQUAL(std::max(alone[0]["mtvv"].get<double>(), alone[1]["mtvv"].get<double>()),
                stats["mtvv"].get<double>(), 0.0);
}

// Today's files read as before: without recording flags, and with --dt at the file's own step,
// the trace is the same bytes; generate --output x.mat writes a MATLAB file whose t and a_u are
// the CSV's doubles.
TEST(RecordingResampling, TodaysCsvAndMatReadToTheSameTraceAndGenerateWritesARealMat) {
  TempDir dir;
  const std::vector<std::string> generate = {"generate",   "--kind", "lorry", "--rms", "1.2",
                                             "--duration", "5",      "--dt",  "0.001"};
  for (const char* name : {"lorry.csv", "lorry.mat"}) {
    std::vector<std::string> arguments = generate;
    arguments.insert(arguments.end(), {"--output", dir.file(name)});
    LONGS_EQUAL(0, run_stickslip(arguments).status);
  }
  CHECK(stickslip::test::read_text(dir.file("lorry.mat")).rfind("MATLAB 5.0 MAT-file", 0) == 0);
  const stickslip::host::SampledSignal csv =
      stickslip::host::read_signal_csv(dir.file("lorry.csv"));
  const stickslip::host::SampledSignal mat =
      stickslip::host::read_signal_mat(dir.file("lorry.mat"));
  LONGS_EQUAL(csv.t_s.size(), mat.t_s.size());
  for (std::size_t n = 0; n < csv.t_s.size(); ++n) {
    CHECK(stickslip::test::bit_equal(csv.t_s[n], mat.t_s[n]));
    CHECK(stickslip::test::bit_equal(csv.a_u_m_per_s2[n], mat.a_u_m_per_s2[n]));
  }
  std::vector<std::string> traces;
  const std::vector<std::vector<std::string>> variants = {
      {"--input", dir.file("lorry.csv")},
      {"--input", dir.file("lorry.csv"), "--dt", "0.001"},
      {"--input", dir.file("lorry.mat")},
      {"--input", dir.file("lorry.mat"), "--dt", "0.001", "--gaps", "refuse"}};
  for (const auto& variant : variants) {
    std::vector<std::string> arguments = {
        "simulate", "--output", dir.file("out.csv"), "--model", "stick-slip", "--ffk", "40"};
    arguments.insert(arguments.end(), variant.begin(), variant.end());
    const auto run = run_stickslip(arguments);
    LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
    STRCMP_EQUAL("", run.err.c_str());  // nothing done to the samples, nothing said
    traces.push_back(stickslip::test::read_text(dir.file("out.csv")));
  }
  for (const std::string& trace : traces) CHECK(trace == traces.front());
}

// A .mat file with a logger's times - jittered, or with a gap - takes the recording options as
// a text file does: the same samples in both give the same trace, byte for byte. Without the
// options it is refused with one line that names the element and points to inspect.
TEST(RecordingResampling, JitteredOrGappedMatRunsWithTheOptionsLikeTheSameCsv) {
  TempDir dir;
  const double longest_step = write_jittered(dir.file("jittered.csv"));
  CHECK(longest_step > 0.002);
  stickslip::host::SampledSignal jittered;
  {
    const stickslip::test::Table table = read_table(dir.file("jittered.csv"));
    jittered.t_s = column(table, 0);
    jittered.a_u_m_per_s2 = column(table, 1);
  }
  stickslip::host::write_signal_mat(dir.file("jittered.mat"), jittered);

  std::string gapped_text = "t,a_u\n";
  stickslip::host::SampledSignal gapped;
  for (int i = 0; i < 4000; ++i) {
    if (i >= 1500 && i < 1620) continue;  // the logger lost 0.12 s
    const double t = i * 0.001;
    gapped_text += csv_row(t, floor_signal(t));
    gapped.t_s.push_back(t);
    gapped.a_u_m_per_s2.push_back(floor_signal(t));
  }
  write_text(dir.file("gapped.csv"), gapped_text);
  stickslip::host::write_signal_mat(dir.file("gapped.mat"), gapped);

  const auto trace_of = [&](const std::string& input, const std::vector<std::string>& flags) {
    std::vector<std::string> arguments = {
        "simulate", "--input",    input,   "--output", dir.file("out.csv"),
        "--model",  "stick-slip", "--ffk", "40"};
    arguments.insert(arguments.end(), flags.begin(), flags.end());
    const auto run = run_stickslip(arguments);
    LONGS_EQUAL_TEXT(0, run.status, run.err.c_str());
    return stickslip::test::read_text(dir.file("out.csv"));
  };
  const std::vector<std::string> regrid = {"--dt", "0.001"};
  const std::vector<std::string> split = {"--gaps", "split"};
  const std::string jittered_trace = trace_of(dir.file("jittered.csv"), regrid);
  CHECK(jittered_trace == trace_of(dir.file("jittered.mat"), regrid));
  const std::string gapped_trace = trace_of(dir.file("gapped.csv"), split);
  CHECK(gapped_trace == trace_of(dir.file("gapped.mat"), split));
  LONGS_EQUAL(4000 - 120, read_table(dir.file("out.csv")).rows.size());

  const auto refused =
      run_stickslip({"simulate", "--input", dir.file("jittered.mat"), "--output",
                     dir.file("refused.csv"), "--model", "stick-slip", "--ffk", "40"});
  LONGS_EQUAL(1, refused.status);
  STRCMP_CONTAINS("jittered.mat: 't' is not uniform at element", refused.err.c_str());
  STRCMP_CONTAINS("stickslip inspect", refused.err.c_str());
  CHECK(!stickslip::test::exists(dir.file("refused.csv")));
}

// A CAN log whose times go backwards is refused with one line naming the log's line of the frame
// (a text log); nothing is written.
TEST(RecordingResampling, ACanLogWhoseTimesGoBackwardsNamesTheFramesLine) {
  TempDir dir;
  write_text(dir.file("bus.asc"),
             "date Fri Nov 27 05:00:00.000 am 2026\n"
             "base hex  timestamps absolute\n"
             "   0.001000 1  100             Rx   d 8 00 00 00 00 00 00 00 00\n"
             "   0.002000 1  100             Rx   d 8 01 00 00 00 00 00 00 00\n"
             "   0.002500 1  181             Rx   d 2 00 00\n"
             "   0.001500 1  100             Rx   d 8 02 00 00 00 00 00 00 00\n");
  const auto run = run_stickslip({"simulate", "--input", dir.file("bus.asc"), "--dbc",
                                  std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc",
                                  "--signal", "SeatInput.a_u", "--output", dir.file("out.csv"),
                                  "--model", "stick-slip", "--ffk", "40"});
  LONGS_EQUAL(1, run.status);
  LONGS_EQUAL(1, stickslip::test::split_lines(run.err).size());
  STRCMP_CONTAINS((dir.file("bus.asc") + ":6: t = 0.0015 s does not come after 0.002 s").c_str(),
                  run.err.c_str());
  CHECK(!stickslip::test::exists(dir.file("out.csv")));
}

// A candump log stamps seconds since the epoch: at 1.8e9 s a double's times are 2.4e-7 s apart,
// so a 1 kHz log's steps differ by up to 2.4e-4 of a step with no jitter in the logger. Such a
// log is uniform: it simulates at its own step without --dt, nothing regridded or resampled, and
// gives the T_ax and p of the same decoded samples in a t,a_u CSV at 1 ms. Its step is the span
// over the steps (span known to 2.4e-7 s over 4 s: 6e-8 relative), so T_ax may differ by that
// order (bound 1e-7); p counts stuck steps, which this dt error cannot change.
TEST(RecordingResampling, ACandumpLogStampedSinceTheEpochIsUniformAtItsOwnStep) {
  TempDir dir;
  std::vector<stickslip::host::LoggedFrame> frames;
  std::string csv = "t,a_u\n";
  for (int n = 0; n <= 4000; ++n) {
    const double t = n * 0.001;
    stickslip::host::LoggedFrame frame;
    frame.time_us = 1795758598288668ull + static_cast<std::uint64_t>(n) * 1000u;
    frame.interface = "can0";
    frame.frame = stickslip::can::make_input_frame(floor_signal(t), static_cast<std::uint64_t>(n));
    frames.push_back(frame);
    csv += csv_row(t, stickslip::can::quantised_input(floor_signal(t)));
  }
  stickslip::host::write_candump_log(dir.file("bus.log"), frames);
  write_text(dir.file("same.csv"), csv);
  const std::vector<std::string> model = {"--model", "stick-slip", "--ffk", "40"};
  std::vector<std::string> from_log = {
      "simulate",
      "--input",
      dir.file("bus.log"),
      "--dbc",
      std::string(STICKSLIP_SOURCE_DIR) + "/docs/can/stickslip.dbc",
      "--signal",
      "SeatInput.a_u",
      "--output",
      dir.file("log.csv")};
  from_log.insert(from_log.end(), model.begin(), model.end());
  std::vector<std::string> from_csv = {"simulate", "--input", dir.file("same.csv"), "--output",
                                       dir.file("csv.csv")};
  from_csv.insert(from_csv.end(), model.begin(), model.end());
  const auto log_run = run_stickslip(from_log);
  LONGS_EQUAL_TEXT(0, log_run.status, log_run.err.c_str());
  const auto csv_run = run_stickslip(from_csv);
  LONGS_EQUAL_TEXT(0, csv_run.status, csv_run.err.c_str());
  const nlohmann::json log_stats = stats_of(log_run), csv_stats = stats_of(csv_run);
  LONGS_EQUAL(0, log_stats["recording"]["regridded_samples"].get<int>());
  CHECK(!log_stats["recording"]["resampled"].get<bool>());
  LONGS_EQUAL(4001, log_stats["samples"].get<int>());
  DOUBLES_EQUAL(0.001, log_stats["dt"].get<double>(), 1e-7 * 0.001);
  const double t_ax = csv_stats["T_ax"].get<double>();
  DOUBLES_EQUAL(t_ax, log_stats["T_ax"].get<double>(), 1e-7 * t_ax);
  DOUBLES_EQUAL(csv_stats["p_stick"].get<double>(), log_stats["p_stick"].get<double>(), 0.0);
}

// Two columns that could be the time: the one named time is, wherever it stands (here after an
// elapsed-time column in s that runs at half speed). And a constant signal has no full scale to
// hit: no clipping is reported for it.
TEST(RecordingResampling, TheColumnNamedTimeIsTheTimeAndAConstantIsNotClipped) {
  TempDir dir;
  std::string text = "Elapsed [s],time,a_u\n";
  for (int n = 0; n < 500; ++n) {
    char row[96];
    std::snprintf(row, sizeof row, "%.17g,%.17g,9.80665\n", 0.002 * n, 0.001 * n);
    text += row;
  }
  write_text(dir.file("in.txt"), text);
  const stickslip::test::CliRun run =
      run_stickslip({"simulate", "--input", dir.file("in.txt"), "--signal", "a_u", "--output",
                     dir.file("out.csv"), "--model", "linear"});
  CHECK_EQUAL(0, run.status);
  const nlohmann::json stats = nlohmann::json::parse(stickslip::test::split_lines(run.out).back());
  DOUBLES_EQUAL(0.001, stats["dt"].get<double>(), 0.0);
  CHECK(run.err.find("clipping") == std::string::npos);
  CHECK(run.out.find("clipping") == std::string::npos);
}
