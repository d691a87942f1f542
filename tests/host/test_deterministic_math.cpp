#include <cmath>
#include <cstdint>

#include "stickslip/host/signals/biquad.hpp"
#include "stickslip/host/signals/deterministic_math.hpp"
#include "stickslip/host/signals/random.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip::host;

// Own log/sin/cos: the generator's reproducibility rests on them, its quality on their accuracy.
TEST_GROUP(DeterministicMath){};

TEST(DeterministicMath, LogAgreesWithLibmToAFewUlp) {
  Xoshiro256StarStar random(11);
  for (int i = 0; i < 200000; ++i) {
    const double x =
        std::ldexp(0.5 + random.uniform(), static_cast<int>(random.next() % 200) - 100);
    const double expected = std::log(x);
    DOUBLES_EQUAL(expected, deterministic_log(x), 4e-16 * std::fabs(expected) + 1e-300);
  }
  DOUBLES_EQUAL(0.0, deterministic_log(1.0), 0.0);
  DOUBLES_EQUAL(std::log(2.0), deterministic_log(2.0), 2e-16);
  DOUBLES_EQUAL(std::log(1e-300), deterministic_log(1e-300), 1e-13);
}

TEST(DeterministicMath, SinCosOfCyclesAgreeWithLibm) {
  const double two_pi = 6.283185307179586476925286766559;
  Xoshiro256StarStar random(12);
  for (int i = 0; i < 200000; ++i) {
    const double cycles = random.uniform();  // reduced already: libm sees an accurate angle
    const SinCos r = deterministic_sincos_cycles(cycles);
    DOUBLES_EQUAL(std::sin(two_pi * cycles), r.sin, 1e-15);
    DOUBLES_EQUAL(std::cos(two_pi * cycles), r.cos, 1e-15);
  }
}

TEST(DeterministicMath, SinCosAreExactAtQuarterCyclesAndPeriodic) {
  DOUBLES_EQUAL(0.0, deterministic_sincos_cycles(0.0).sin, 0.0);
  DOUBLES_EQUAL(1.0, deterministic_sincos_cycles(0.0).cos, 0.0);
  DOUBLES_EQUAL(1.0, deterministic_sincos_cycles(0.25).sin, 0.0);
  DOUBLES_EQUAL(-1.0, deterministic_sincos_cycles(0.5).cos, 0.0);
  DOUBLES_EQUAL(-1.0, deterministic_sincos_cycles(0.75).sin, 0.0);
  // Whole cycles are removed exactly: a phase late in a long recording keeps its accuracy.
  const SinCos early = deterministic_sincos_cycles(0.3);
  const SinCos late = deterministic_sincos_cycles(1048576.3 - 0.0);  // 0.3 after 2^20 cycles
  DOUBLES_EQUAL(early.sin, late.sin, 1e-9);
  DOUBLES_EQUAL(early.cos, late.cos, 1e-9);
  DOUBLES_EQUAL(std::tan(3.14159265358979323846 * 0.1), deterministic_tan_half_cycles(0.1), 1e-15);
}

// The published reference sequences, so that "same seed, same file" holds for any port.
TEST_GROUP(Random){};

TEST(Random, SplitMix64MatchesItsReferenceSequence) {
  SplitMix64 mixer(1234567);
  const std::uint64_t expected[] = {6457827717110365317ull, 3203168211198807973ull,
                                    9817491932198370423ull, 4593380528125082431ull,
                                    16408922859458223821ull};
  for (std::uint64_t value : expected) CHECK_EQUAL(value, mixer.next());
}

TEST(Random, Xoshiro256StarStarMatchesItsReferenceSequence) {
  Xoshiro256StarStar generator = Xoshiro256StarStar::from_state(1, 2, 3, 4);
  const std::uint64_t expected[] = {11520ull, 0ull, 1509978240ull, 1215971899390074240ull};
  for (std::uint64_t value : expected) CHECK_EQUAL(value, generator.next());
}

TEST(Random, StreamsOfOneSeedDiffer) {
  Xoshiro256StarStar a(5, 1), b(5, 2), c(5, 1);
  const std::uint64_t first_a = a.next();
  CHECK(first_a != b.next());
  CHECK_EQUAL(first_a, c.next());
}

TEST(Random, GaussianHasZeroMeanUnitVarianceAndNormalTails) {
  GaussianSource gaussian(3);
  const int count = 400000;
  double sum = 0.0, sum_sq = 0.0;
  int beyond_two_sigma = 0;
  for (int i = 0; i < count; ++i) {
    const double x = gaussian.next();
    sum += x;
    sum_sq += x * x;
    if (std::fabs(x) > 2.0) ++beyond_two_sigma;
  }
  const double mean = sum / count;
  const double variance = sum_sq / count - mean * mean;
  DOUBLES_EQUAL(0.0, mean, 0.01);  // 5 standard errors
  DOUBLES_EQUAL(1.0, variance, 0.012);
  DOUBLES_EQUAL(0.0455, static_cast<double>(beyond_two_sigma) / count, 0.002);  // P(|x| > 2)
}

namespace {
// |H(e^{j 2 pi f dt})| of one section.
double magnitude(const Biquad& f, double frequency_hz, double dt_s) {
  const double w = 6.283185307179586 * frequency_hz * dt_s;
  const double c1 = std::cos(w), s1 = std::sin(w), c2 = std::cos(2 * w), s2 = std::sin(2 * w);
  const double num_re = f.b0 + f.b1 * c1 + f.b2 * c2, num_im = -(f.b1 * s1 + f.b2 * s2);
  const double den_re = 1.0 + f.a1 * c1 + f.a2 * c2, den_im = -(f.a1 * s1 + f.a2 * s2);
  return std::sqrt((num_re * num_re + num_im * num_im) / (den_re * den_re + den_im * den_im));
}
}  // namespace

TEST_GROUP(Biquad){};

TEST(Biquad, ButterworthQualitiesAreTheTextbookValues) {
  DOUBLES_EQUAL(0.70710678118654752, butterworth_quality(2, 0), 1e-15);
  DOUBLES_EQUAL(0.54119610014619698, butterworth_quality(4, 0), 1e-15);
  DOUBLES_EQUAL(1.3065629648763766, butterworth_quality(4, 1), 1e-14);
}

TEST(Biquad, SectionsHaveUnitPassbandAndHalfPowerAtTheirCorner) {
  const double dt = 1e-3;
  const double q = butterworth_quality(2, 0);
  const Biquad low = design_lowpass(20.0, q, dt);
  DOUBLES_EQUAL(1.0, magnitude(low, 0.0, dt), 1e-12);
  DOUBLES_EQUAL(std::sqrt(0.5), magnitude(low, 20.0, dt), 1e-12);  // pre-warped: exact at f0
  const Biquad high = design_highpass(0.5, q, dt);
  DOUBLES_EQUAL(1.0, magnitude(high, 499.999, dt), 1e-9);
  DOUBLES_EQUAL(std::sqrt(0.5), magnitude(high, 0.5, dt), 1e-9);
  const Biquad band = design_bandpass(2.0, 0.7, dt);
  DOUBLES_EQUAL(1.0, magnitude(band, 2.0, dt), 1e-12);
  CHECK(magnitude(band, 20.0, dt) < 0.2);
}

TEST(Biquad, CascadeFiltersAStepToItsDcGain) {
  BiquadCascade cascade;
  add_butterworth_lowpass(cascade, 4, 20.0, 1e-3);
  double y = 0.0;
  for (int n = 0; n < 2000; ++n) y = cascade.process(1.0);
  DOUBLES_EQUAL(1.0, y, 1e-12);
}
