// Resampling a uniform recording onto the model's step (signals/resample.hpp, libsoxr VHQ) up to
// the record's first and last samples: the record is continued past its ends by odd reflection,
// so a constant (gravity, a sensor's bias) or a ramp comes out unchanged at every output sample
// and a sine well inside the pass band is off near the ends only by the filter's response to the
// continuation's curvature jump.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

#include "stickslip/host/signals/resample.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using stickslip::host::resample_step;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.80665;
constexpr double kModelStepS = 0.001;
constexpr double kRatesHz[] = {500.0, 400.0, 200.0, 2000.0};

// soxr VHQ's gain error at and near 0 Hz, measured over every output sample of 4 s records:
// 3.0e-10 (500 Hz), 1.8e-9 (400 Hz), 8.1e-11 (200 Hz), 1.5e-10 (2000 Hz into 1 kHz). The
// tolerance is the largest of them with a margin under 3 for other lengths, not rounding: the
// polyphase filter's DC gain differs by phase.
constexpr double kDcGainError = 5e-9;

// Half the filter's support in seconds: 150 samples of the lower rate, where the measured
// impulse responses fall below 1e-11 of their peak.
double support_s(double rate_hz) {
  return 150.0 / std::min(rate_hz, 1.0 / kModelStepS);
}

std::vector<double> sampled(double rate_hz, double duration_s, double (*f)(double)) {
  const auto count = static_cast<std::size_t>(duration_s * rate_hz) + 1;
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i) values[i] = f(static_cast<double>(i) / rate_hz);
  return values;
}

// The output grid of resample_step: every k dt within the record's span.
std::size_t grid_count(std::size_t samples, double rate_hz) {
  return static_cast<std::size_t>(
             std::floor(static_cast<double>(samples - 1) / rate_hz / kModelStepS + 1e-6)) +
         1;
}

double gravity(double) {
  return kGravity;
}
double ramp(double t_s) {
  return 1.0 + 2.5 * t_s;
}

constexpr double kSineHz = 23.0;
constexpr double kSinePhase = 0.7;
double sine(double t_s) {
  return std::sin(2.0 * kPi * kSineHz * t_s + kSinePhase);
}

}  // namespace

TEST_GROUP(Resample){};

TEST(Resample, AConstantIsThatConstantAtEveryOutputSampleIncludingTheFirstAndLast) {
  for (const double rate_hz : kRatesHz) {
    const std::vector<double> in = sampled(rate_hz, 4.0, gravity);
    const std::vector<double> out = resample_step(in, 1.0 / rate_hz, kModelStepS);
    LONGS_EQUAL(grid_count(in.size(), rate_hz), out.size());
    double worst = 0.0;
    for (const double a : out) worst = std::max(worst, std::fabs(a - kGravity) / kGravity);
    std::printf("\n  %g Hz: constant worst relative error %.2g", rate_hz, worst);
    DOUBLES_EQUAL(kGravity, out.front(), kDcGainError * kGravity);
    DOUBLES_EQUAL(kGravity, out.back(), kDcGainError * kGravity);
    CHECK(worst <= kDcGainError);
  }
}

// A ramp is what odd reflection continues exactly (value and slope), so it too goes through
// with only the gain error, relative to its value at each sample.
TEST(Resample, ALinearRampIsThatRampAtEveryOutputSampleIncludingTheFirstAndLast) {
  for (const double rate_hz : kRatesHz) {
    const std::vector<double> in = sampled(rate_hz, 4.0, ramp);
    const std::vector<double> out = resample_step(in, 1.0 / rate_hz, kModelStepS);
    LONGS_EQUAL(grid_count(in.size(), rate_hz), out.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double expected = ramp(static_cast<double>(k) * kModelStepS);
      DOUBLES_EQUAL(expected, out[k], kDcGainError * expected);
    }
  }
}

// A 23 Hz sine, within 0.23 of the lowest Nyquist frequency here (100 Hz). Farther than the
// filter's support from the ends it is the analytic sine to the filter's pass-band accuracy
// (measured 1.4e-10 to 9.5e-10; allowed 5e-9, as for the constant). Near the ends the odd
// continuation 2 x(0) - x(-t) has the sine's value and slope but the opposite curvature: the
// band-limited filter answers a curvature jump of 2 w^2 |sin phase| with an error of that order
// times 1 / w_N^2 (w_N the lower Nyquist frequency); measured 0.22 to 0.25 of
// (f / f_N)^2 at the rates here (0.07 from 2 kHz), so 0.3 (f / f_N)^2 is allowed. Before the
// continuation, soxr's zeros gave errors of 6 to 16 % of the amplitude there.
TEST(Resample, ASineInsideThePassBandIsTheAnalyticSineAwayFromAndNearTheEnds) {
  for (const double rate_hz : kRatesHz) {
    const std::vector<double> in = sampled(rate_hz, 4.0, sine);
    const std::vector<double> out = resample_step(in, 1.0 / rate_hz, kModelStepS);
    const double span_s = static_cast<double>(in.size() - 1) / rate_hz;
    const double nyquist_hz = 0.5 * std::min(rate_hz, 1.0 / kModelStepS);
    const double near_bound = 0.3 * std::pow(kSineHz / nyquist_hz, 2.0);
    double near = 0.0, away = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double t = static_cast<double>(k) * kModelStepS;
      const double error = std::fabs(out[k] - sine(t));
      const bool is_near = t < support_s(rate_hz) || t > span_s - support_s(rate_hz);
      (is_near ? near : away) = std::max(is_near ? near : away, error);
    }
    std::printf("\n  %g Hz: sine near the ends %.3g (bound %.3g), away %.3g", rate_hz, near,
                near_bound, away);
    CHECK(near <= near_bound);
    CHECK(away <= kDcGainError);
  }
}

// A rate whose ratio to the model's is no ratio of small integers (a logger's mean step): no
// padding puts the record's grid on the padded record's, so the start is continued by its value
// only. A constant is still exact there (it is subtracted before the filter and added after).
TEST(Resample, AConstantAtARateWithNoSmallIntegerRatioIsExactToo) {
  const double rate_hz = 499.97;
  const std::vector<double> in = sampled(rate_hz, 4.0, gravity);
  const std::vector<double> out = resample_step(in, 1.0 / rate_hz, kModelStepS);
  LONGS_EQUAL(grid_count(in.size(), rate_hz), out.size());
  for (const double a : out) DOUBLES_EQUAL(kGravity, a, kDcGainError * kGravity);
}
