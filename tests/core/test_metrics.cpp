// The run metrics: RMS, transmissibility and stick probability from RunningStatistics, and Den
// Hartog's friction factor, against closed forms.
#include <cmath>
#include <cstdint>
#include <limits>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"

using namespace stickslip;
using stickslip::test::kPi;

TEST_GROUP(RunningStatistics){};

// Over whole periods (P >= 3 samples each) the mean of sin^2 is exactly 1/2, so a sampled sine of
// amplitude A has RMS A/sqrt(2) and the ratio of two such sines is B/A, whatever the phases.
TEST(RunningStatistics, SampledSinesOverWholePeriodsGiveAmplitudeOverRootTwo) {
  const double a = 0.35, b = 0.81;
  const int period = 37, periods = 2000;
  RunningStatistics<double> stats;
  for (int n = 0; n < period * periods; ++n) {
    const double phase = 2.0 * kPi * n / period;
    stats.add_sample(a * std::sin(phase + 0.3), b * std::sin(phase - 1.1));
  }
  UNSIGNED_LONGS_EQUAL(period * periods, stats.samples());
  DOUBLES_EQUAL(a / std::sqrt(2.0), stats.rms_u(), 1e-13);
  DOUBLES_EQUAL(b / std::sqrt(2.0), stats.rms_x(), 1e-13);
  DOUBLES_EQUAL(b / a, stats.transmissibility(), 1e-12);
}

// p is the stuck time over the total time: the mean of the per-step stuck fractions.
TEST(RunningStatistics, StickProbabilityIsTheMeanStuckFraction) {
  RunningStatistics<double> stats;
  const double fractions[] = {0.0, 1.0, 0.25, 1.0, 0.0, 0.75, 0.5, 1.0};  // sum 4.5
  for (int repeat = 0; repeat < 1000; ++repeat)
    for (double f : fractions) stats.add_step(f);
  UNSIGNED_LONGS_EQUAL(8000, stats.steps());
  DOUBLES_EQUAL(4.5 / 8.0, stats.stick_probability(), 1e-15);
  DOUBLES_EQUAL(4500.0 * 1e-3, stats.stuck_time_s(1e-3), 1e-12);
}

// 1e7 float samples: a plain float sum of 0.09 reaches 9e5, where one ulp is 0.0625, so each
// addition would be off by up to a third of itself. The blocked, compensated sums promise an error
// of about (block + a few) ulp of the total however long the run: (256 + 4) eps relative on the
// sums, half of it on the RMS.
TEST(RunningStatistics, FloatStatisticsStayAccurateOverTenMillionSamples) {
  RunningStatistics<float> stats;
  const float u = 0.3f, x = 0.12f;
  for (int n = 0; n < 10000000; ++n) {
    stats.add_sample(u, x);
    stats.add_step(0.37f);
  }
  const double bound = (RunningStatistics<float>::kBlockSamples + 4) *
                       static_cast<double>(std::numeric_limits<float>::epsilon());
  const double u_error = std::fabs(stats.rms_u() / static_cast<double>(u) - 1.0);
  const double x_error = std::fabs(stats.rms_x() / static_cast<double>(x) - 1.0);
  const double p_error = std::fabs(stats.stick_probability() / static_cast<double>(0.37f) - 1.0);
  CHECK_TEXT(u_error < 0.5 * bound,
             StringFromFormat("rms_u rel. error %.3e", u_error).asCharString());
  CHECK_TEXT(x_error < 0.5 * bound,
             StringFromFormat("rms_x rel. error %.3e", x_error).asCharString());
  CHECK_TEXT(p_error < bound, StringFromFormat("p rel. error %.3e", p_error).asCharString());
  test::note_margin("float 1e7-sample rms_u rel. error", u_error, 0.5 * bound);
  test::note_margin("float 1e7-sample p rel. error", p_error, bound);
}

// No samples, or an identically zero input: the metrics are 0, not NaN.
TEST(RunningStatistics, EmptyOrZeroInputGivesZeroNotNan) {
  RunningStatistics<double> stats;
  CHECK_EQUAL(0.0, stats.rms_u());
  CHECK_EQUAL(0.0, stats.transmissibility());
  CHECK_EQUAL(0.0, stats.stick_probability());
  for (int n = 0; n < 100; ++n) stats.add_sample(0.0, 0.0);
  CHECK_EQUAL(0.0, stats.transmissibility());
  stats.add_sample(1.0, 2.0);
  stats.add_step(1.0);
  stats.reset();
  UNSIGNED_LONGS_EQUAL(0, stats.samples());
  UNSIGNED_LONGS_EQUAL(0, stats.steps());
  CHECK_EQUAL(0.0, stats.rms_x());
}

TEST_GROUP(DenHartog){};

// K = 4 F_fk / (pi sqrt(2) m a0u).
TEST(DenHartog, FactorIsTheClosedForm) {
  const double k = den_hartog_factor(35.0, test::kMassKg, 0.35);
  DOUBLES_EQUAL(4.0 * 35.0 / (kPi * std::sqrt(2.0) * test::kMassKg * 0.35), k, 1e-15);
  DOUBLES_EQUAL(1.0,
                den_hartog_factor(test::kinetic_friction_for_den_hartog(1.0, 70.0, 0.5), 70.0, 0.5),
                1e-15);
  CHECK_EQUAL(0.0, den_hartog_factor(0.0, test::kMassKg, 0.35));   // no friction
  CHECK(std::isinf(den_hartog_factor(35.0, test::kMassKg, 0.0)));  // friction, no input
}

// Regimes: below 0.4 signum suffices, above 0.75 only stick-slip is right, in between transition.
TEST(DenHartog, RegimeThresholds) {
  CHECK(friction_regime(0.0) == FrictionRegime::signum_suffices);
  CHECK(friction_regime(0.399) == FrictionRegime::signum_suffices);
  CHECK(friction_regime(0.4) == FrictionRegime::transition);
  CHECK(friction_regime(0.75) == FrictionRegime::transition);
  CHECK(friction_regime(0.751) == FrictionRegime::stick_slip_required);
  CHECK(friction_regime(std::numeric_limits<double>::infinity()) ==
        FrictionRegime::stick_slip_required);
}
