// The signal generator (signal_generator.hpp) in memory: the spectra of its kinds, the file
// it writes holds the in-memory signal, and validation refuses what cannot be generated.
#include <cmath>
#include <string>
#include <vector>

#include "stickslip/host/error.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip::host;
using stickslip::test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

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
};

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

TEST(Generator, ValidateThrowsUsageErrors) {
  CHECK_THROWS(UsageError, validate(spec(SignalKind::wideband, 1.0, 1.0, 0.0, 1)));
  validate(spec(SignalKind::wideband, 1.0, 1.0, 0.001, 1));  // fine: no throw
  LONGS_EQUAL(1001, sample_count(spec(SignalKind::wideband, 1.0, 1.0, 0.001, 1)));
}
