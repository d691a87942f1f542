// Linear seat (no friction) with the exact integrator against the analytic frequency response.
//
// The oracle accounts for the first-order hold: the input is a sampled sine, interpolated linearly
// between samples, whose steady state at the sample instants is the aliased-FRF sum of
// oracles.hpp. The continuous H(i w) alone would differ by ~(w dt)^2/12 (1.3e-3 at 20 Hz, 1 ms),
// six orders above the tolerance, so these tests do see the input model.
#include <algorithm>
#include <cmath>
#include <complex>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

constexpr double kFrfTolerance = 1e-9;

struct FrfErrors {
  double complex_amplitude = 0.0;  // |S_fit - S| / |S|
  double amplitude = 0.0;          // ||S_fit|/|S| - 1|
  double phase_rad = 0.0;          // |arg(S_fit / S)|
  double pointwise_x = 0.0;        // max |x[n] - x_oracle[n]| / |S_x|
  double pointwise_v = 0.0;        // max |v[n] - v_oracle[n]| / |S_v|
};

// Runs a_u[n] = sin(w n dt) through the linear seat from (x0, v0) and compares the samples of the
// window [settle_s, settle_s + window_s] with the steady state Im(e^{i w t_n} S).
FrfErrors run_sine(double frequency_hz, double dt_s, double damping, double x0, double v0,
                   double settle_s, double window_s) {
  const double w = 2.0 * kPi * frequency_hz;
  const auto oracle =
      test::foh_phasor_response(test::kMassKg, damping, test::kStiffnessNPerM, w, dt_s);
  Oscillator<double, NoFriction> seat;
  const auto config = seat.configure(
      test::reference_params(FrictionModel::linear, Integrator::exact, dt_s, damping));
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(x0, v0, 0.0);  // a_u[0] = sin(0) = 0

  const long settle = std::lround(settle_s / dt_s);
  const long end = settle + std::lround(window_s / dt_s);
  // Least-squares fit of x[n] = p sin(theta_n) + q cos(theta_n), S_fit = p + i q.
  double ss = 0.0, sc = 0.0, cc = 0.0, xs = 0.0, xc = 0.0;
  FrfErrors e;
  const double x_scale = std::abs(oracle.x_m), v_scale = std::abs(oracle.v_m_per_s);
  for (long n = 1; n <= end; ++n) {
    const double t = static_cast<double>(n) * dt_s;
    const double theta = w * t;
    const double s = std::sin(theta), c = std::cos(theta);
    const auto out = seat.step(s);
    if (n < settle) continue;
    const double x_expected = oracle.x_m.real() * s + oracle.x_m.imag() * c;
    const double v_expected = oracle.v_m_per_s.real() * s + oracle.v_m_per_s.imag() * c;
    e.pointwise_x = std::max(e.pointwise_x, std::fabs(out.x_r_m - x_expected) / x_scale);
    e.pointwise_v = std::max(e.pointwise_v, std::fabs(out.v_r_m_per_s - v_expected) / v_scale);
    ss += s * s;
    sc += s * c;
    cc += c * c;
    xs += out.x_r_m * s;
    xc += out.x_r_m * c;
  }
  const double det = ss * cc - sc * sc;
  const std::complex<double> fit((xs * cc - xc * sc) / det, (xc * ss - xs * sc) / det);
  e.complex_amplitude = std::abs(fit - oracle.x_m) / x_scale;
  e.amplitude = std::fabs(std::abs(fit) / x_scale - 1.0);
  e.phase_rad = std::fabs(std::arg(fit / oracle.x_m));
  return e;
}

void check_within_tolerance(const FrfErrors& e, double frequency_hz, double dt_s) {
  const SimpleString where = StringFromFormat("f = %g Hz, dt = %g s", frequency_hz, dt_s);
  CHECK_TEXT(e.complex_amplitude < kFrfTolerance,
             StringFromFormat("%s: complex amplitude rel. error %.3e", where.asCharString(),
                              e.complex_amplitude)
                 .asCharString());
  CHECK_TEXT(e.amplitude < kFrfTolerance,
             StringFromFormat("%s: amplitude rel. error %.3e", where.asCharString(), e.amplitude)
                 .asCharString());
  CHECK_TEXT(e.phase_rad < kFrfTolerance,
             StringFromFormat("%s: phase error %.3e rad", where.asCharString(), e.phase_rad)
                 .asCharString());
  CHECK_TEXT(e.pointwise_x < kFrfTolerance,
             StringFromFormat("%s: pointwise x error %.3e", where.asCharString(), e.pointwise_x)
                 .asCharString());
  CHECK_TEXT(e.pointwise_v < kFrfTolerance,
             StringFromFormat("%s: pointwise v error %.3e", where.asCharString(), e.pointwise_v)
                 .asCharString());
}

double worst(const FrfErrors& e) {
  return std::max({e.complex_amplitude, e.amplitude, e.phase_rad, e.pointwise_x, e.pointwise_v});
}

}  // namespace

TEST_GROUP(LinearFrequencyResponse){};

// From rest with b = 504 N s/m (sigma = 2.85 1/s): after 14 s the transient is below 1e-16 of the
// steady state, which must then match the FOH frequency response at every frequency and step.
TEST(LinearFrequencyResponse, DampedSteadyStateMatchesSampledFrfAmplitudeAndPhase) {
  const double frequencies_hz[] = {0.5, 1.8, 5.0, 20.0};
  const double steps_s[] = {1e-3, 1e-4};
  double worst_error = 0.0;
  for (double dt : steps_s) {
    for (double f : frequencies_hz) {
      const double window = std::max(4.0, 2.0 / f);  // at least two periods
      const FrfErrors e = run_sine(f, dt, test::kDampingNsPerM, 0.0, 0.0, 14.0, window);
      check_within_tolerance(e, f, dt);
      worst_error = std::max(worst_error, worst(e));
    }
  }
  test::note_margin("damped FRF worst relative error", worst_error, kFrfTolerance);
}

// The hold matters: at 20 Hz and dt = 1 ms the continuous H(i w) is ~1e-3 away from the sampled
// steady state, so matching the latter to 1e-9 proves the integrator applies the FOH input exactly.
TEST(LinearFrequencyResponse, SteadyStateFollowsTheFirstOrderHoldNotTheContinuousFrf) {
  const double w = 2.0 * kPi * 20.0, dt = 1e-3;
  const auto oracle =
      test::foh_phasor_response(test::kMassKg, test::kDampingNsPerM, test::kStiffnessNPerM, w, dt);
  const auto continuous =
      test::seat_frf(test::kMassKg, test::kDampingNsPerM, test::kStiffnessNPerM, w);
  CHECK(std::abs(oracle.x_m - continuous) > 1e-4 * std::abs(continuous));
  const FrfErrors e = run_sine(20.0, dt, test::kDampingNsPerM, 0.0, 0.0, 14.0, 2.0);
  check_within_tolerance(e, 20.0, dt);
}

// b = 0: no transient decays, so start exactly on the steady state (x(0), v(0) from the sum) and
// the exact integrator must stay on it, off resonance, below and above it.
TEST(LinearFrequencyResponse, UndampedStartOnSteadyStateStaysOnIt) {
  const double frequencies_hz[] = {0.5, 5.0, 20.0};
  const double steps_s[] = {1e-3, 1e-4};
  double worst_error = 0.0;
  for (double dt : steps_s) {
    for (double f : frequencies_hz) {
      const double w = 2.0 * kPi * f;
      const auto oracle =
          test::foh_phasor_response(test::kMassKg, 0.0, test::kStiffnessNPerM, w, dt);
      // At t = 0 the steady state is Im(S) (theta = 0).
      const FrfErrors e = run_sine(f, dt, 0.0, oracle.x_m.imag(), oracle.v_m_per_s.imag(), 0.0,
                                   std::max(6.0, 2.0 / f));
      check_within_tolerance(e, f, dt);
      worst_error = std::max(worst_error, worst(e));
    }
  }
  test::note_margin("undamped FRF worst relative error", worst_error, kFrfTolerance);
}

// The same oracle must reject a wrong start: starting the undamped seat from rest leaves a free
// oscillation that never decays, far above the tolerance (the comparison can fail).
TEST(LinearFrequencyResponse, UndampedStartFromRestIsNotTheSteadyState) {
  const FrfErrors e = run_sine(5.0, 1e-3, 0.0, 0.0, 0.0, 0.0, 6.0);
  CHECK(e.pointwise_x > 1e-3);
}
