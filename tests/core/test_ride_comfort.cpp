// ISO 2631-1 frequency weightings (Wk, Wd) and the streaming ride-comfort figures.
#include <cfenv>
#include <cmath>
#include <cstddef>
#include <limits>

#include "CppUTest/TestHarness.h"
#include "stickslip/metrics/iso2631_weighting.hpp"
#include "stickslip/metrics/ride_comfort.hpp"

using stickslip::BiquadCoefficients;
using stickslip::ComfortWeighting;
using stickslip::RideComfort;
using stickslip::WeightingFilter;

namespace {

constexpr double kPi = 3.14159265358979323846;

// ISO 2631-1:1997 Table 3 (weighting factors, not x1000) at the one-third-octave bands 0.5-80 Hz
// (nominal frequencies; the factors belong to the exact band centres 10^(n/10) Hz).
constexpr std::size_t kBands = 23;
constexpr double kNominalHz[kBands] = {0.5, 0.63, 0.8,  1,  1.25, 1.6, 2,    2.5, 3.15, 4,  5, 6.3,
                                       8,   10,   12.5, 16, 20,   25,  31.5, 40,  50,   63, 80};
constexpr double kTableWk[kBands] = {0.418, 0.459, 0.477, 0.482, 0.484, 0.494, 0.531, 0.631,
                                     0.804, 0.967, 1.039, 1.054, 1.036, 0.988, 0.902, 0.768,
                                     0.636, 0.513, 0.405, 0.314, 0.246, 0.186, 0.132};
constexpr double kTableWd[kBands] = {0.853, 0.944,  0.992,  1.011,  1.008,  0.968,  0.890, 0.776,
                                     0.642, 0.512,  0.409,  0.323,  0.253,  0.212,  0.161, 0.125,
                                     0.100, 0.0800, 0.0632, 0.0494, 0.0388, 0.0295, 0.0211};
// Wd at 10 Hz: the table's 0.212 is off the standard's own formula (0.2017) and its neighbours'
// 1/f slope (0.253 * 8/10 = 0.202); it is compared with the formula's tolerance widened to 5 %.
constexpr std::size_t kWdTenHz = 13;

double exact_band_centre(double nominal_hz) {
  return std::pow(10.0, std::round(10.0 * std::log10(nominal_hz)) / 10.0);
}

double decibels(double ratio) {
  return 20.0 * std::log10(ratio);
}

}  // namespace

TEST_GROUP(ComfortWeighting){};

// The analogue definition (ISO 2631-1 Annex A with the ISO 8041 parameters) reproduces the
// standard's table, which is rounded to three significant figures.
TEST(ComfortWeighting, AnalogueDefinitionReproducesTheTabulatedFactors) {
  for (std::size_t i = 0; i < kBands; ++i) {
    const double f = exact_band_centre(kNominalHz[i]);
    const double wk = stickslip::analogue_weighting_magnitude(ComfortWeighting::wk, f);
    const double wd = stickslip::analogue_weighting_magnitude(ComfortWeighting::wd, f);
    DOUBLES_EQUAL(kTableWk[i], wk, 0.02 * kTableWk[i]);
    DOUBLES_EQUAL(kTableWd[i], wd, (i == kWdTenHz ? 0.05 : 0.02) * kTableWd[i]);
  }
}

// The digital cascade designed for the sample rate stays within 0.5 dB of the table at every
// tabulated band from 0.5 to 80 Hz, at 200 Hz (80 Hz is then 0.8 Nyquist), 500 Hz, 1 kHz and 5 kHz.
TEST(ComfortWeighting, DigitalCascadeStaysWithinHalfADecibelOfTheTable) {
  for (const double fs : {200.0, 500.0, 1000.0, 5000.0}) {
    for (const ComfortWeighting w : {ComfortWeighting::wk, ComfortWeighting::wd}) {
      BiquadCoefficients sections[stickslip::kWeightingSections];
      CHECK_TRUE(stickslip::design_weighting(w, fs, sections).ok());
      const double* table = w == ComfortWeighting::wk ? kTableWk : kTableWd;
      for (std::size_t i = 0; i < kBands; ++i) {
        const double f = exact_band_centre(kNominalHz[i]);
        const double digital = stickslip::digital_weighting_magnitude(sections, fs, f);
        CHECK_TRUE(std::fabs(decibels(digital / table[i])) <= 0.5);
        // Against the definition itself (no table rounding); measured: 0.31 dB at 200 Hz (at the
        // 80 Hz band), at most 0.005 dB from 500 Hz up.
        const double analogue = stickslip::analogue_weighting_magnitude(w, f);
        CHECK_TRUE(std::fabs(decibels(digital / analogue)) <= (fs >= 500.0 ? 0.01 : 0.35));
      }
    }
  }
}

// The filter's difference equation is the designed cascade: a steady sine comes out scaled by the
// cascade's magnitude at that frequency (double and float).
TEST(ComfortWeighting, SteadySineIsScaledByTheCascadeMagnitude) {
  const double fs = 1000.0;
  for (const double f : {0.8, 5.0, 31.5}) {
    WeightingFilter<double> wd;
    WeightingFilter<float> wf;
    CHECK_TRUE(wd.configure(ComfortWeighting::wk, fs).ok());
    CHECK_TRUE(wf.configure(ComfortWeighting::wk, fs).ok());
    const double expected = stickslip::digital_weighting_magnitude(wd.sections(), fs, f);
    // 20 s to settle (the 0.4 Hz high-pass), then whole periods.
    const auto settle = static_cast<std::size_t>(20.0 * fs);
    const auto periods = static_cast<std::size_t>(std::round(std::ceil(10.0 * f) * fs / f));
    double sum_d = 0.0, sum_f = 0.0, sum_in = 0.0;
    for (std::size_t n = 0; n < settle + periods; ++n) {
      const double x = std::sin(2 * kPi * f * static_cast<double>(n) / fs);
      const double yd = wd.step(x);
      const double yf = static_cast<double>(wf.step(static_cast<float>(x)));
      if (n >= settle) {
        sum_d += yd * yd;
        sum_f += yf * yf;
        sum_in += x * x;
      }
    }
    DOUBLES_EQUAL(expected, std::sqrt(sum_d / sum_in), 2e-3 * expected);
    DOUBLES_EQUAL(expected, std::sqrt(sum_f / sum_in), 5e-3 * expected);
  }
}

TEST(ComfortWeighting, RefusesSampleRatesItCannotServe) {
  BiquadCoefficients sections[stickslip::kWeightingSections];
  CHECK_TRUE(stickslip::design_weighting(ComfortWeighting::wk, 0.0, sections).status ==
             stickslip::Status::out_of_range);
  CHECK_TRUE(stickslip::design_weighting(ComfortWeighting::wk,
                                         std::numeric_limits<double>::quiet_NaN(), sections)
                 .status == stickslip::Status::not_finite);
  const stickslip::ConfigResult low =
      stickslip::design_weighting(ComfortWeighting::wd, 1.0, sections);
  CHECK_FALSE(low.ok());
  STRCMP_CONTAINS("sample_rate_hz", low.message.c_str());
}

TEST_GROUP(RideComfort){};

// A steady sine: weighted RMS = A |W(f)| / sqrt2, VDV = A |W(f)| (3T/8)^(1/4), MTVV just above
// the weighted RMS (the 1 s window ripples at 2f), crest factor close to sqrt2.
TEST(RideComfort, SteadySineGivesTheClosedFormFigures) {
  const double fs = 1000.0, f = 5.0, amplitude = 0.7, duration = 120.0;
  RideComfort<double> comfort;
  CHECK_TRUE(comfort.configure(ComfortWeighting::wk, fs).ok());
  const auto count = static_cast<std::size_t>(duration * fs);
  for (std::size_t n = 0; n < count; ++n) {
    const double t = static_cast<double>(n) / fs;
    // A 2 s raised-cosine fade-in keeps the high-pass transient out of the peak.
    const double fade = t < 2.0 ? 0.5 - 0.5 * std::cos(kPi * t / 2.0) : 1.0;
    const double a = fade * amplitude * std::sin(2 * kPi * f * t);
    comfort.add_sample(a, 0.5 * a);
  }
  BiquadCoefficients sections[stickslip::kWeightingSections];
  CHECK_TRUE(stickslip::design_weighting(ComfortWeighting::wk, fs, sections).ok());
  const double w = stickslip::digital_weighting_magnitude(sections, fs, f);
  const double rms = amplitude * w / std::sqrt(2.0);
  DOUBLES_EQUAL(rms, comfort.floor_weighted_rms(), 0.01 * rms);  // the fade-in is 1.7 % of the run
  DOUBLES_EQUAL(0.5 * rms, comfort.seat_weighted_rms(), 0.01 * rms);
  DOUBLES_EQUAL(0.5, comfort.seat_ratio(), 1e-12);  // a linear filter: exactly half, to rounding
  const double vdv = 0.5 * amplitude * w * std::pow(3.0 * duration / 8.0, 0.25);
  DOUBLES_EQUAL(vdv, comfort.seat_vdv(), 0.01 * vdv);
  CHECK_TRUE(comfort.seat_mtvv() >= comfort.seat_weighted_rms());
  DOUBLES_EQUAL(0.5 * rms, comfort.seat_mtvv(), 0.02 * rms);
  DOUBLES_EQUAL(std::sqrt(2.0), comfort.seat_crest_factor(), 0.02);
  CHECK_EQUAL(count, comfort.samples());
}

// A shock: one short burst in a quiet run drives MTVV and the crest factor up while the overall
// weighted RMS stays small; the VDV, a fourth-power measure, sees it more than the RMS does.
TEST(RideComfort, ShockRaisesMtvvAndCrestFactorAboveTheOverallRms) {
  const double fs = 1000.0;
  RideComfort<float> comfort;
  CHECK_TRUE(comfort.configure(ComfortWeighting::wk, fs).ok());
  for (std::size_t n = 0; n < 60000; ++n) {
    const double t = static_cast<double>(n) / fs;
    double a = 0.05 * std::sin(2 * kPi * 4.0 * t);
    if (t >= 30.0 && t < 30.25) a += 3.0 * std::sin(2 * kPi * 4.0 * (t - 30.0));
    comfort.add_sample(0.0f, static_cast<float>(a));
  }
  CHECK_TRUE(comfort.seat_crest_factor() > 9.0);  // ISO 2631-1: the basic method is not enough
  CHECK_TRUE(comfort.seat_mtvv() > 5.0 * comfort.seat_weighted_rms());
  const double rms_based_vdv = 1.4 * comfort.seat_weighted_rms() * std::pow(60.0, 0.25);
  CHECK_TRUE(comfort.seat_vdv() > rms_based_vdv);  // eVDV underestimates shocks
  DOUBLES_EQUAL(0.0, comfort.seat_ratio(), 0.0);   // no floor motion: SEAT reported as 0
}

// A floor and seat barely moving (the weighting's start-up on a quantised sample gives the same):
// weighted samples whose fourth power would be subnormal count as 0 and raise no FE_UNDERFLOW
// (found by the simulate == replay property: the float observer's VDV sum underflowed).
TEST(RideComfort, TinyWeightedSamplesRaiseNoUnderflow) {
  RideComfort<float> comfort;
  CHECK_TRUE(comfort.configure(ComfortWeighting::wk, 1000.0).ok());
  std::feclearexcept(FE_ALL_EXCEPT);
  for (std::size_t n = 0; n < 2000; ++n) comfort.add_sample(1e-9f, n % 2 == 0 ? 1e-9f : -1e-9f);
  CHECK_FALSE(std::fetestexcept(FE_UNDERFLOW));
  CHECK_TRUE(comfort.seat_weighted_rms() < 1e-9);
  CHECK_TRUE(std::isfinite(comfort.seat_vdv()) && std::isfinite(comfort.seat_crest_factor()));
}

TEST(RideComfort, RefusesAWindowShorterThanOneSample) {
  RideComfort<double> comfort;
  const stickslip::ConfigResult result = comfort.configure(ComfortWeighting::wd, 1000.0, 1e-4);
  CHECK_FALSE(result.ok());
  STRCMP_CONTAINS("running_rms_time_s", result.message.c_str());
  CHECK_FALSE(comfort.configure(ComfortWeighting::wd, 0.0).ok());
}
