#include <cmath>
#include <string>
#include <vector>

#include "host_test_support.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip::host;
using stickslip::test::CliRun;
using stickslip::test::run_stickslip;
using stickslip::test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

double rms(const std::vector<double>& x) {
  long double sum = 0.0L;
  for (double v : x) sum += static_cast<long double>(v) * static_cast<long double>(v);
  return static_cast<double>(std::sqrt(sum / static_cast<long double>(x.size())));
}

// Power of the Hann-windowed signal at one frequency (a single DFT term at any frequency).
double power_at(const std::vector<double>& x, double frequency_hz, double dt_s) {
  const std::size_t count = x.size();
  double re = 0.0, im = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    const double window =
        0.5 - 0.5 * std::cos(2.0 * kPi * static_cast<double>(n) / static_cast<double>(count - 1));
    double cycles = frequency_hz * static_cast<double>(n) * dt_s;
    cycles -= std::floor(cycles);
    re += window * x[n] * std::cos(2.0 * kPi * cycles);
    im -= window * x[n] * std::sin(2.0 * kPi * cycles);
  }
  return re * re + im * im;
}

// Mean power over `count` frequencies evenly spread over [low, high].
double mean_power(const std::vector<double>& x, double low_hz, double high_hz, int count,
                  double dt_s) {
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    sum += power_at(x, low_hz + (high_hz - low_hz) * i / (count - 1), dt_s);
  }
  return sum / count;
}

double max_power(const std::vector<double>& x, double low_hz, double high_hz, int count,
                 double dt_s) {
  double best = 0.0;
  for (int i = 0; i < count; ++i) {
    const double p = power_at(x, low_hz + (high_hz - low_hz) * i / (count - 1), dt_s);
    if (p > best) best = p;
  }
  return best;
}

GeneratorSpec spec(SignalKind kind, double rms_value, double duration, double dt,
                   std::uint64_t seed, double frequency = 0.0) {
  GeneratorSpec s;
  s.kind = kind;
  s.rms_m_per_s2 = rms_value;
  s.duration_s = duration;
  s.dt_s = dt;
  s.seed = seed;
  s.frequency_hz = frequency;
  return s;
}

}  // namespace

TEST_GROUP(Generator) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }

  CliRun generate(const std::string& kind, const std::string& seed, const std::string& file,
                  const std::string& duration = "20", const std::string& dt = "0.001") {
    return run_stickslip({"generate", "--kind", kind, "--rms", "0.35", "--duration", duration,
                          "--dt", dt, "--seed", seed, "--frequency", "3", "--output",
                          dir.file(file)});
  }
};

TEST(Generator, SameSeedGivesIdenticalBytesAndAnotherSeedDifferent) {
  for (const char* kind : {"wideband", "lorry"}) {
    LONGS_EQUAL(0, generate(kind, "42", "a.csv").status);
    LONGS_EQUAL(0, generate(kind, "42", "b.csv").status);
    LONGS_EQUAL(0, generate(kind, "43", "c.csv").status);
    const std::string a = stickslip::test::read_text(dir.file("a.csv"));
    CHECK_TRUE(a.size() > 100000);
    CHECK_TRUE(a == stickslip::test::read_text(dir.file("b.csv")));
    CHECK_FALSE(a == stickslip::test::read_text(dir.file("c.csv")));
  }
}

// Pins the exact bytes: with our own PRNG, Gaussian, log/sin/cos and filters (no libm, no
// <random>, no FMA) these are the same on every machine; a change here changes recordings.
TEST(Generator, FilesAreTheSameOnEveryMachine) {
  LONGS_EQUAL(0, generate("wideband", "1", "w.csv", "2", "0.01").status);
  LONGS_EQUAL(0, generate("lorry", "1", "l.csv", "2", "0.01").status);
  LONGS_EQUAL(0, generate("harmonic", "1", "h.csv", "2", "0.01").status);
  const auto head = [&](const std::string& file) {
    return stickslip::test::split_lines(stickslip::test::read_text(dir.file(file))).at(2);
  };
  STRCMP_EQUAL("0.01,-0.50191113273326415", head("w.csv").c_str());
  STRCMP_EQUAL("0.01,0.90352844981386005", head("l.csv").c_str());
  STRCMP_EQUAL("0.01,0.092980602176382196", head("h.csv").c_str());
  CHECK_EQUAL(16209717020812864016ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("w.csv"))));
  CHECK_EQUAL(18264029936581452316ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("l.csv"))));
  CHECK_EQUAL(5705278269092566359ull,
              stickslip::test::fnv1a(stickslip::test::read_text(dir.file("h.csv"))));
}

TEST(Generator, WritesOneRowPerSampleWithTFromTheIndexAndTheRequestedRms) {
  for (const char* kind : {"wideband", "lorry", "harmonic"}) {
    const CliRun run = generate(kind, "5", "g.csv", "12.3456", "0.001");
    LONGS_EQUAL(0, run.status);
    STRCMP_EQUAL("", run.err.c_str());
    const stickslip::test::Table table = stickslip::test::read_table(dir.file("g.csv"));
    CHECK_TRUE(table.ok);
    LONGS_EQUAL(2, table.header.size());
    STRCMP_EQUAL("t", table.header[0].c_str());
    STRCMP_EQUAL("a_u", table.header[1].c_str());
    LONGS_EQUAL(12347, table.rows.size());  // n = 0..round(12.3456/0.001) = 12346
    for (std::size_t n = 0; n < table.rows.size(); ++n) {
      CHECK_TRUE(stickslip::test::bit_equal(static_cast<double>(n) * 0.001, table.rows[n][0]));
    }
    const double measured = rms(stickslip::test::column(table, 1));
    DOUBLES_EQUAL(0.35, measured, 0.35 * 1e-12);
  }
}

TEST(Generator, InMemorySignalIsWhatTheFileHolds) {
  const GeneratorSpec s = spec(SignalKind::lorry, 0.35, 3.0, 0.002, 9);
  const std::vector<double> memory = generate_signal(s);
  LONGS_EQUAL(1501, memory.size());
  LONGS_EQUAL(1501, write_generated_csv(s, dir.file("m.csv")));
  const std::vector<double> file =
      stickslip::test::column(stickslip::test::read_table(dir.file("m.csv")), 1);
  LONGS_EQUAL(memory.size(), file.size());
  for (std::size_t n = 0; n < file.size(); ++n)
    CHECK_TRUE(stickslip::test::bit_equal(memory[n], file[n]));
}

TEST(Generator, WidebandKeepsItsEnergyBetweenHalfAndTwentyHertz) {
  const double dt = 0.01;
  const std::vector<double> x = generate_signal(spec(SignalKind::wideband, 1.0, 200.0, dt, 3));
  const double pass = mean_power(x, 1.0, 15.0, 60, dt);
  const double below = mean_power(x, 0.02, 0.3, 30, dt);
  const double above = mean_power(x, 30.0, 48.0, 40, dt);
  CHECK_TRUE(below < 0.05 * pass);
  CHECK_TRUE(above < 0.05 * pass);
  // Flat inside the band: the edges of the pass band hold about as much as its middle.
  const double low_edge = mean_power(x, 1.0, 3.0, 40, dt);
  const double high_edge = mean_power(x, 12.0, 16.0, 40, dt);
  CHECK_TRUE(low_edge > 0.5 * high_edge && low_edge < 2.0 * high_edge);
}

TEST(Generator, LorryShowsEngineOrderPeaksOverABroadbandHumpAtOneToThreeHertz) {
  const double dt = 0.01;
  const std::vector<double> x = generate_signal(spec(SignalKind::lorry, 0.35, 200.0, dt, 1));
  const double peak_1 = max_power(x, 6.25, 6.35, 21, dt);
  const double around_1 = mean_power(x, 5.0, 5.8, 30, dt) + mean_power(x, 6.9, 7.7, 30, dt);
  const double peak_2 = max_power(x, 12.55, 12.65, 21, dt);
  const double around_2 = mean_power(x, 11.0, 12.0, 30, dt) + mean_power(x, 13.2, 14.2, 30, dt);
  CHECK_TRUE(peak_1 > 100.0 * around_1);
  CHECK_TRUE(peak_2 > 100.0 * around_2);
  const double hump = mean_power(x, 1.0, 3.0, 60, dt);
  CHECK_TRUE(hump > 5.0 * mean_power(x, 0.05, 0.3, 30, dt));
  CHECK_TRUE(hump > 20.0 * mean_power(x, 20.0, 30.0, 40, dt));
}

TEST(Generator, HarmonicIsASineAtTheRequestedFrequency) {
  const double dt = 0.001;
  const std::vector<double> x = generate_signal(spec(SignalKind::harmonic, 2.0, 10.0, dt, 1, 2.5));
  const double amplitude = 2.0 * std::sqrt(2.0);  // 25 whole periods: RMS = amplitude / sqrt(2)
  for (std::size_t n = 0; n < x.size(); n += 7) {
    DOUBLES_EQUAL(amplitude * std::sin(2.0 * kPi * 2.5 * static_cast<double>(n) * dt), x[n], 1e-3);
  }
}

TEST(Generator, InvalidRequestsAreRefusedWithoutAFile) {
  struct Case {
    std::vector<std::string> arguments;
    const char* message;
  };
  const std::string out = dir.file("bad.csv");
  const Case cases[] = {
      {{"--kind", "pink", "--rms", "1", "--duration", "1", "--dt", "0.001"},
       "--kind: unknown kind 'pink'"},
      {{"--kind", "wideband", "--rms", "0", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got 0"},
      {{"--kind", "wideband", "--rms", "-1", "--duration", "1", "--dt", "0.001"},
       "--rms: must be a finite number > 0, got -1"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "0", "--dt", "0.001"},
       "--duration: must be a finite number > 0"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1", "--dt", "0"},
       "--dt: must be a finite number > 0"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "0.0001", "--dt", "0.001"},
       "shorter than one step"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1e7", "--dt", "1e-3"},
       "more than the limit"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "10", "--dt", "0.03"},
       "--dt: wideband needs 0.5/dt above 20 Hz"},
      {{"--kind", "lorry", "--rms", "1", "--duration", "10", "--dt", "0.03"},
       "--dt: lorry needs 0.5/dt above 20 Hz"},
      {{"--kind", "harmonic", "--rms", "1", "--duration", "1", "--dt", "0.001"},
       "--frequency: harmonic needs 0 < frequency < 0.5/dt = 500 Hz, got 0"},
      {{"--kind", "harmonic", "--rms", "1", "--duration", "1", "--dt", "0.001", "--frequency",
        "500"},
       "--frequency: harmonic needs"},
      {{"--kind", "wideband", "--rms", "abc", "--duration", "1", "--dt", "0.001"}, "--rms"},
      {{"--kind", "wideband", "--rms", "1", "--duration", "1"}, "--dt is required"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> arguments{"generate"};
    arguments.insert(arguments.end(), c.arguments.begin(), c.arguments.end());
    arguments.insert(arguments.end(), {"--output", out});
    const CliRun run = run_stickslip(arguments);
    LONGS_EQUAL(2, run.status);
    STRCMP_CONTAINS(c.message, run.err.c_str());
    STRCMP_CONTAINS("stickslip: ", run.err.c_str());
    LONGS_EQUAL(1, stickslip::test::split_lines(run.err).size());
    LONGS_EQUAL(0, dir.entries().size());
  }
}

TEST(Generator, ValidateThrowsUsageErrors) {
  CHECK_THROWS(UsageError, validate(spec(SignalKind::wideband, 1.0, 1.0, 0.0, 1)));
  validate(spec(SignalKind::wideband, 1.0, 1.0, 0.001, 1));  // fine: no throw
  LONGS_EQUAL(1001, sample_count(spec(SignalKind::wideband, 1.0, 1.0, 0.001, 1)));
}
