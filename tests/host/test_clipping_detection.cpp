// Runs at full scale (RecordingReport::clipped_samples, docs/RECORDINGS.md "What is reported"):
// a signal cut flat at its limit is counted, a coarsely quantized signal that merely dwells at
// its top and bottom levels (a CAN signal of 0.1 m/s^2 per bit) is not.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "stickslip/host/run/recording_source.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::test::TempDir;
using stickslip::test::write_text;
namespace host = stickslip::host;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRateHz = 500.0;

// The samples as a text file of columns t and acc (the text reader, which counts the runs).
std::size_t clipped_in(const TempDir& dir, const std::vector<double>& a) {
  std::string text = "t,acc\n";
  char row[64];
  for (std::size_t n = 0; n < a.size(); ++n) {
    std::snprintf(row, sizeof row, "%.17g,%.17g\n", static_cast<double>(n) / kRateHz, a[n]);
    text += row;
  }
  const std::string path = dir.file("a.csv");
  write_text(path, text);
  host::RecordingOptions options;
  options.signal = "acc";
  return host::read_recording(path, options).report.clipped_samples;
}

// Samples in runs of >= 3 equal values at the minimum or maximum, by the test's own loop.
std::size_t runs_at_extremes(const std::vector<double>& a) {
  double low = a.front(), high = a.front();
  for (double x : a) low = std::min(low, x), high = std::max(high, x);
  std::size_t in_runs = 0;
  for (std::size_t i = 0; i < a.size();) {
    std::size_t end = i;
    while (end < a.size() && a[end] == a[i]) ++end;
    if (end - i >= 3 && (a[i] == low || a[i] == high)) in_runs += end - i;
    i = end;
  }
  return in_runs;
}

// Rounded to 0.1 m/s^2 per bit, as a DBC factor of 0.1 decodes it.
double quantized(double a) {
  return std::round(a / 0.1) * 0.1;
}

}  // namespace

TEST_GROUP(ClippingDetection) {
  TempDir dir;
  void setup() override {
    CHECK_TRUE(dir.ok());
  }
};

TEST(ClippingDetection, AQuantizedSignalDwellingAtItsPeakLevelsIsNoClipping) {
  std::vector<double> a;
  for (int n = 0; n < 2000; ++n) {
    const double t = n / kRateHz;
    a.push_back(quantized(0.45 * std::sin(2 * kPi * 1.3 * t) + 0.2 * std::sin(2 * kPi * 4.1 * t)));
  }
  CHECK(runs_at_extremes(a) > 20);  // what the plain run count took for clipping
  LONGS_EQUAL(0, clipped_in(dir, a));
}

TEST(ClippingDetection, ASineCutFlatAt80PercentOfItsPeakIsClipping) {
  for (const bool quantize : {false, true}) {
    std::vector<double> a;
    for (int n = 0; n < 2000; ++n) {
      const double t = n / kRateHz;
      const double sine = 3.0 * std::sin(2 * kPi * 1.3 * t);
      const double cut = std::max(-2.4, std::min(2.4, sine));
      a.push_back(quantize ? quantized(cut) : cut);
    }
    const std::size_t expected = runs_at_extremes(a);
    CHECK(expected > 500);  // about 30 % of a period at each peak
    // Every plateau is counted; quantized, the last (cut short by the end of the file, its
    // slope seen on one side over 21 samples only) may not be.
    const std::size_t clipped = clipped_in(dir, a);
    CHECK_TEXT(clipped <= expected && clipped >= expected * 9 / 10,
               std::to_string(clipped).c_str());
  }
}
