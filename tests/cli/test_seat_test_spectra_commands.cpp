// The seat-test spectra and recordings through the command line: generate writes the standard's
// signal deterministically at its level, a .mat recording simulates like the same samples in CSV,
// and psd puts a sine's power at its frequency.
#include <matio.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip::host;
using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_GROUP(SeatTestSpectra){};

TEST(SeatTestSpectra, GenerateCommandIsDeterministicAndUsesTheStandardLevel) {
  TempDir dir;
  const auto generate = [&](const char* kind, const char* seed, const char* file) {
    return run_stickslip({"generate", "--kind", kind, "--duration", "600", "--dt", "0.001",
                          "--seed", seed, "--output", dir.file(file)});
  };
  LONGS_EQUAL(0, generate("EM6", "3", "a.csv").status);
  LONGS_EQUAL(0, generate("em6", "3", "b.csv").status);
  LONGS_EQUAL(0, generate("EM6", "4", "c.csv").status);
  const std::string a = stickslip::test::read_text(dir.file("a.csv"));
  CHECK_TRUE(a == stickslip::test::read_text(dir.file("b.csv")));
  CHECK_FALSE(a == stickslip::test::read_text(dir.file("c.csv")));
  const std::vector<double> values = read_signal_csv(dir.file("a.csv")).a_u_m_per_s2;
  // The streamed file holds exactly the in-memory signal.
  SpectrumSignalSpec spec;
  spec.spectrum = *find_seat_test_spectrum("EM6");
  spec.duration_s = 600.0;
  spec.dt_s = 0.001;
  spec.seed = 3;
  CHECK_TRUE(generate_spectrum_signal(spec) == values);
  double sum = 0.0;
  for (double v : values) sum += v * v;
  const double rms = std::sqrt(sum / static_cast<double>(values.size()));
  // The standard's level (EM6's table value to 50 Hz is 1.73; 600 s of a ~5 Hz wide band
  // scatter by about 1 %).
  DOUBLES_EQUAL(1.73, rms, 0.05);
  const CliRun white = run_stickslip({"generate", "--kind", "white", "--duration", "1", "--dt",
                                      "0.001", "--output", dir.file("w.csv")});
  LONGS_EQUAL(2, white.status);
  STRCMP_CONTAINS("--rms is required for white", white.err.c_str());
  const CliRun coarse = run_stickslip({"generate", "--kind", "EM6", "--duration", "10", "--dt",
                                       "0.05", "--output", dir.file("x.csv")});
  LONGS_EQUAL(2, coarse.status);
  STRCMP_CONTAINS("corner at 9 Hz", coarse.err.c_str());
}

TEST_GROUP(MatFile) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

// A .mat written by matio itself (single-precision a_u and a scalar dt, as a logger might save
// them) simulates exactly like the same samples in CSV.
TEST(MatFile, MatRecordingSimulatesLikeTheSameCsv) {
  const std::size_t n = 2001;
  std::vector<float> a_u(n);
  for (std::size_t i = 0; i < n; ++i)
    a_u[i] = static_cast<float>(0.5 * std::sin(0.02 * static_cast<double>(i)));
  double dt = 0.001;
  {
    mat_t* file = Mat_CreateVer(dir.file("rec.mat").c_str(), nullptr, MAT_FT_MAT5);
    CHECK_TRUE(file != nullptr);
    std::size_t dims[2] = {1, n};
    matvar_t* v = Mat_VarCreate("a_u", MAT_C_SINGLE, MAT_T_SINGLE, 2, dims, a_u.data(), 0);
    LONGS_EQUAL(0, Mat_VarWrite(file, v, MAT_COMPRESSION_NONE));
    Mat_VarFree(v);
    std::size_t one[2] = {1, 1};
    matvar_t* d = Mat_VarCreate("dt", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &dt, 0);
    LONGS_EQUAL(0, Mat_VarWrite(file, d, MAT_COMPRESSION_NONE));
    Mat_VarFree(d);
    Mat_Close(file);
  }
  const SampledSignal read = read_signal_mat(dir.file("rec.mat"));
  LONGS_EQUAL(n, read.a_u_m_per_s2.size());
  for (std::size_t i = 0; i < n; ++i) {
    CHECK_TRUE(stickslip::test::bit_equal(static_cast<double>(a_u[i]), read.a_u_m_per_s2[i]));
    CHECK_TRUE(stickslip::test::bit_equal(static_cast<double>(i) * dt, read.t_s[i]));
  }
  std::string csv = "t,a_u\n";
  char line[80];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", read.t_s[i], read.a_u_m_per_s2[i]);
    csv += line;
  }
  stickslip::test::write_text(dir.file("rec.csv"), csv);
  for (const char* input : {"rec.mat", "rec.csv"}) {
    const CliRun run = run_stickslip({"simulate", "--input", dir.file(input), "--output",
                                      dir.file(std::string(input) + ".out"), "--model",
                                      "stick-slip", "--ffk", "20"});
    LONGS_EQUAL(0, run.status);
  }
  CHECK_TRUE(stickslip::test::read_text(dir.file("rec.mat.out")) ==
             stickslip::test::read_text(dir.file("rec.csv.out")));

  // write_signal_mat -> read_signal_mat round trip with a t vector.
  write_signal_mat(dir.file("t.mat"), read);
  const SampledSignal again = read_signal_file(dir.file("t.mat"));
  CHECK_TRUE(again.t_s == read.t_s);
  CHECK_TRUE(again.a_u_m_per_s2 == read.a_u_m_per_s2);
  DOUBLES_EQUAL(dt, again.dt_s, 1e-15);
}

TEST(MatFile, MissingVariablesAreNamed) {
  SampledSignal signal;
  signal.t_s = {0.0, 0.1, 0.2};
  signal.a_u_m_per_s2 = {1.0, 2.0, 3.0};
  write_signal_mat(dir.file("ok.mat"), signal);
  {
    mat_t* file = Mat_CreateVer(dir.file("none.mat").c_str(), nullptr, MAT_FT_MAT5);
    double x[2] = {1.0, 2.0};
    std::size_t dims[2] = {2, 1};
    matvar_t* v = Mat_VarCreate("acc", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, x, 0);
    Mat_VarWrite(file, v, MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
    Mat_Close(file);
  }
  const CliRun run = run_stickslip({"simulate", "--input", dir.file("none.mat"), "--output",
                                    dir.file("o.csv"), "--model", "linear"});
  LONGS_EQUAL(1, run.status);
  STRCMP_CONTAINS("no variable 'a_u'", run.err.c_str());
  CHECK_FALSE(stickslip::test::exists(dir.file("o.csv")));
  stickslip::test::write_text(dir.file("junk.mat"), "not a mat file");
  const CliRun junk = run_stickslip({"simulate", "--input", dir.file("junk.mat"), "--output",
                                     dir.file("o.csv"), "--model", "linear"});
  LONGS_EQUAL(1, junk.status);
  STRCMP_CONTAINS("junk.mat", junk.err.c_str());
}

TEST_GROUP(Psd){};

// stickslip psd: a sine's power sits at its frequency, and the PSD integrates to the variance
// (Parseval, Hann window with its power normalisation).
TEST(Psd, SineIsAtItsFrequencyAndThePsdIntegratesToTheVariance) {
  TempDir dir;
  const std::size_t n = 40001;
  std::string csv = "t,a_u\n";
  char line[80];
  double variance = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * 0.005;
    const double a = 0.7 * std::sin(2.0 * kPi * 12.5 * t);
    variance += a * a;
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", t, a);
    csv += line;
  }
  variance /= static_cast<double>(n);
  stickslip::test::write_text(dir.file("sine.csv"), csv);
  const CliRun run = run_stickslip({"psd", "--input", dir.file("sine.csv"), "--segment", "2048",
                                    "--target", "EM6", "--output", dir.file("psd.csv")});
  LONGS_EQUAL(0, run.status);
  const stickslip::test::Table table = stickslip::test::read_table(dir.file("psd.csv"));
  CHECK_TRUE(table.ok);
  LONGS_EQUAL(1025, table.rows.size());
  STRCMP_EQUAL("target", table.header[2].c_str());
  double integral = 0.0, best = 0.0, best_f = 0.0;
  const double df = table.rows[1][0];
  DOUBLES_EQUAL(1.0 / (2048 * 0.005), df, 1e-12);
  for (const auto& row : table.rows) {
    integral += row[1] * df;
    if (row[1] > best) {
      best = row[1];
      best_f = row[0];
    }
    DOUBLES_EQUAL(target_psd(*find_seat_test_spectrum("EM6"), row[0]), row[2], 1e-15);
  }
  DOUBLES_EQUAL(12.5, best_f, df);
  DOUBLES_EQUAL(variance, integral, 0.01 * variance);
}
