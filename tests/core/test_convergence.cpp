// Observed orders of the integrators, and convergence of stick-slip to the event-driven solution.
//
// Linear model: free decay from initial conditions has a closed form, and with a sampled input the
// exact integrator at the same dt is the exact solution for the same first-order-hold input (so
// the hold's own O(dt^2) interpolation error does not pollute the observed orders).
// Stick-slip: with Coulomb friction the motion between events is linear with a piecewise-linear
// input, so the exact integrator with in-step events is exact whatever dt; a run at dt = 1 ms
// must agree with one at 1e-5 s fed the linear interpolation of the same samples.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"

using namespace stickslip;
using stickslip::test::kPi;

namespace {

// Closed-form free decay of the linear seat from (x0, v0): under-damped (b = 0 included) or
// over-damped.
void free_decay(double damping, double x0, double v0, double t, double& x, double& v) {
  const double omega0_sq = test::kStiffnessNPerM / test::kMassKg;
  const double sigma = damping / (2.0 * test::kMassKg);
  // sqrt of |discriminant| in both branches: clang may evaluate both speculatively, and a sqrt
  // of a negative number would raise FE_INVALID (the IEEE754 plugin fails the test).
  const double discriminant = std::fabs(omega0_sq - sigma * sigma);
  if (sigma * sigma < omega0_sq) {
    // x = e^{-sigma t}(x0 cos wd t + B sin wd t), B = (v0 + sigma x0)/wd.
    const double wd = std::sqrt(discriminant);
    const double decay = std::exp(-sigma * t);
    const double c = std::cos(wd * t), s = std::sin(wd * t);
    const double b_coef = (v0 + sigma * x0) / wd;
    x = decay * (x0 * c + b_coef * s);
    v = decay * ((-sigma * x0 + wd * b_coef) * c + (-sigma * b_coef - wd * x0) * s);
  } else {
    // x = c1 e^{r1 t} + c2 e^{r2 t}, r1,2 = -sigma +- sqrt(sigma^2 - omega0^2).
    const double root = std::sqrt(discriminant);
    const double r1 = -sigma + root, r2 = -sigma - root;
    const double c1 = (v0 - r2 * x0) / (r1 - r2), c2 = x0 - c1;
    const double e1 = std::exp(r1 * t), e2 = std::exp(r2 * t);
    x = c1 * e1 + c2 * e2;
    v = c1 * r1 * e1 + c2 * r2 * e2;
  }
}

// Max error in x_r over [0, T] of the linear seat's free decay against the closed form.
double free_decay_error(Integrator integrator, double damping, double dt, double duration) {
  const double x0 = 0.03, v0 = -0.2;
  Oscillator<double, NoFriction> seat;
  const auto config =
      seat.configure(test::reference_params(FrictionModel::linear, integrator, dt, damping));
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(x0, v0, 0.0);
  const long steps = std::lround(duration / dt);
  double worst = 0.0;
  for (long n = 1; n <= steps; ++n) {
    const auto out = seat.step(0.0);
    double x = 0.0, v = 0.0;
    free_decay(damping, x0, v0, static_cast<double>(n) * dt, x, v);
    worst = std::max(worst, std::fabs(out.x_r_m - x));
  }
  return worst;
}

// A smooth two-tone input, sampled.
double smooth_input(double t) {
  return 0.8 * std::sin(2.0 * kPi * 2.0 * t) + 0.5 * std::sin(2.0 * kPi * 5.3 * t + 1.0);
}

// Max error in x_r over [0, T] against the exact integrator fed the same samples.
double sampled_input_error(Integrator integrator, double dt, double duration) {
  Oscillator<double, NoFriction> seat, reference;
  const auto params = test::reference_params(FrictionModel::linear, integrator, dt);
  auto reference_params = params;
  reference_params.integrator = Integrator::exact;
  CHECK(seat.configure(params).ok());
  CHECK(reference.configure(reference_params).ok());
  seat.reset(0.0, 0.0, smooth_input(0.0));
  reference.reset(0.0, 0.0, smooth_input(0.0));
  const long steps = std::lround(duration / dt);
  double worst = 0.0;
  for (long n = 1; n <= steps; ++n) {
    const double a = smooth_input(static_cast<double>(n) * dt);
    worst = std::max(worst, std::fabs(seat.step(a).x_r_m - reference.step(a).x_r_m));
  }
  return worst;
}

// Observed orders log2(e(dt)/e(dt/2)) over successive halvings, all within 0.1 of `order`.
template <typename ErrorFn>
void check_observed_order(const char* what, double order, double dt0, int halvings, ErrorFn error) {
  double previous = error(dt0);
  double dt = dt0;
  for (int i = 0; i < halvings; ++i) {
    dt *= 0.5;
    const double current = error(dt);
    const double observed = std::log2(previous / current);
    CHECK_TEXT(
        std::fabs(observed - order) < 0.1,
        StringFromFormat("%s: observed order %.3f at dt = %g (errors %.3e -> %.3e), expected %g",
                         what, observed, dt, previous, current, order)
            .asCharString());
    test::note_margin(what, observed, order);
    previous = current;
  }
}

// ---- stick-slip on a lorry-like signal ------------------------------------------------------

constexpr double kLorryRms = 0.35;       // m/s^2
constexpr double kLorryKineticN = 35.0;  // K = 1.02 at 0.35 m/s^2: well into stick-slip
constexpr double kLorryStaticN = 45.0;

OscillatorParams lorry_params(double dt) {
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact, dt);
  p.kinetic_friction_n = kLorryKineticN;
  p.static_friction_n = kLorryStaticN;
  return p;
}

struct LorryResult {
  double transmissibility = 0.0;
  double stick_probability = 0.0;
  std::vector<double> x_at_coarse;  // x_r at the coarse sample instants
  std::uint64_t budget_exhausted = 0;
};

// Runs `coarse` (dt_coarse) refined `ratio` times by linear interpolation.
LorryResult run_lorry(const std::vector<double>& coarse, double dt_coarse, std::size_t ratio) {
  const double dt = dt_coarse / static_cast<double>(ratio);
  Oscillator<double, CoulombStickSlip> seat;
  const auto config = seat.configure(lorry_params(dt));
  CHECK_TEXT(config.ok(), config.message.c_str());
  seat.reset(0.0, 0.0, coarse[0]);
  RunningStatistics<double> stats;
  stats.add_sample(coarse[0], seat.current().a_x_m_per_s2);
  LorryResult r;
  r.x_at_coarse.reserve(coarse.size());
  r.x_at_coarse.push_back(0.0);
  const std::size_t steps = (coarse.size() - 1) * ratio;
  for (std::size_t j = 1; j <= steps; ++j) {
    const double a = test::refine_linear(coarse, j, ratio);
    const auto out = seat.step(a);
    stats.add_sample(a, out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    if (j % ratio == 0) r.x_at_coarse.push_back(out.x_r_m);
  }
  r.transmissibility = stats.transmissibility();
  r.stick_probability = stats.stick_probability();
  r.budget_exhausted = seat.event_budget_exhausted();
  return r;
}

}  // namespace

TEST_GROUP(Convergence){};

// Free decay: the closed form is exact for any input-free run, so each scheme shows its own order.
TEST(Convergence, FreeDecayEulerIsFirstOrder) {
  check_observed_order("euler free decay order", 1.0, 1e-3, 3, [](double dt) {
    return free_decay_error(Integrator::euler, test::kDampingNsPerM, dt, 2.0);
  });
}

TEST(Convergence, FreeDecaySymplecticIsFirstOrder) {
  for (double b : {test::kDampingNsPerM, 0.0}) {
    check_observed_order("symplectic free decay order", 1.0, 1e-3, 3, [b](double dt) {
      return free_decay_error(Integrator::symplectic, b, dt, 2.0);
    });
  }
}

TEST(Convergence, FreeDecayRk4IsFourthOrder) {
  for (double b : {test::kDampingNsPerM, 0.0}) {
    check_observed_order("rk4 free decay order", 4.0, 8e-3, 3,
                         [b](double dt) { return free_decay_error(Integrator::rk4, b, dt, 2.0); });
  }
}

// The exact integrator has no discretisation error at all: rounding only, at every dt.
TEST(Convergence, FreeDecayExactIsExactAtAnyStep) {
  double worst = 0.0;
  for (double dt : {1e-4, 1e-3, 1e-2, 0.05, 0.2}) {
    for (double b : {test::kDampingNsPerM, 0.0, 4032.0 /* zeta = 2 */}) {
      const double e = free_decay_error(Integrator::exact, b, dt, 2.0);
      CHECK_TEXT(e < 1e-13,
                 StringFromFormat("dt = %g b = %g: error %.3e m", dt, b, e).asCharString());
      worst = std::max(worst, e);
    }
  }
  test::note_margin("exact free decay max error, m", worst, 1e-13);
}

// Sampled smooth input, against the exact integrator on the same first-order-hold input.
TEST(Convergence, SampledInputOrdersAgainstExactOnTheSameHold) {
  check_observed_order("euler FOH-input order", 1.0, 1e-3, 3,
                       [](double dt) { return sampled_input_error(Integrator::euler, dt, 3.0); });
  check_observed_order("symplectic FOH-input order", 1.0, 1e-3, 3, [](double dt) {
    return sampled_input_error(Integrator::symplectic, dt, 3.0);
  });
  check_observed_order("rk4 FOH-input order", 4.0, 8e-3, 3,
                       [](double dt) { return sampled_input_error(Integrator::rk4, dt, 3.0); });
}

// Stick instant of the constant-input release (t = pi/w_d, closed form) with every integrator:
// the event is located inside the step with each scheme's own sub-step maps, so its error falls
// at the scheme's order (euler, symplectic 1, rk4 4) and the exact integrator is exact.
double stick_instant_error(Integrator integrator, double dt) {
  const double a_u = 1.5, kinetic = 40.0, static_n = 50.0;
  const auto chain = test::coulomb_half_cycles(test::kMassKg, test::kStiffnessNPerM,
                                               test::kDampingNsPerM, kinetic, static_n, a_u, 0.0);
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, integrator, dt);
  p.kinetic_friction_n = kinetic;
  p.static_friction_n = static_n;
  Oscillator<double, CoulombStickSlip> seat;
  CHECK(seat.configure(p).ok());
  seat.reset(0.0, 0.0, a_u);
  for (long j = 1; j < 100000; ++j) {
    const auto out = seat.step(a_u);
    if (out.stuck) return std::fabs(static_cast<double>(j) * dt - out.stuck_time_s - chain.stop_s);
  }
  FAIL("never stuck");
  return 0.0;
}

TEST(Convergence, StickInstantConvergesAtEachIntegratorsOrder) {
  check_observed_order("euler stick instant order", 1.0, 2e-3, 3,
                       [](double dt) { return stick_instant_error(Integrator::euler, dt); });
  check_observed_order("symplectic stick instant order", 1.0, 2e-3, 3,
                       [](double dt) { return stick_instant_error(Integrator::symplectic, dt); });
  check_observed_order("rk4 stick instant order", 4.0, 4e-3, 3,
                       [](double dt) { return stick_instant_error(Integrator::rk4, dt); });
  for (double dt : {4e-3, 1e-3, 2.5e-4}) CHECK(stick_instant_error(Integrator::exact, dt) < 1e-13);
}

// Event-driven exactness: on the same piecewise-linear input, stick-slip with the exact integrator
// at dt = 10 ms and at 1e-5 s (1000 times finer) pass through the same states at every 10 ms.
TEST(Convergence, StickSlipExactAgreesAcrossStepsOnTheSameInput) {
  const auto signal = test::make_lorry_signal(11, kLorryRms);
  const double dt_coarse = 1e-2;
  const auto coarse = signal.sample(dt_coarse, 1001);  // 10 s
  const LorryResult a = run_lorry(coarse, dt_coarse, 1);
  const LorryResult b = run_lorry(coarse, dt_coarse, 1000);
  double worst = 0.0;
  for (std::size_t n = 0; n < coarse.size(); ++n)
    worst = std::max(worst, std::fabs(a.x_at_coarse[n] - b.x_at_coarse[n]));
  CHECK_TEXT(worst < 1e-8,
             StringFromFormat("max |x(10 ms) - x(1e-5 s)| = %.3e m", worst).asCharString());
  CHECK(a.stick_probability > 0.2);  // the case does stick and slip
  CHECK(a.stick_probability < 0.95);
  CHECK_EQUAL(0u, a.budget_exhausted);
  CHECK_EQUAL(0u, b.budget_exhausted);
  test::note_margin("stick-slip 10 ms vs 1e-5 s max state difference, m", worst, 1e-8);
}

// The accuracy target: 120 s of lorry-like input, stick-slip at dt = 1 ms within 0.1 % in T_ax
// and 0.005 in p of the same model at dt = 1e-5 s on the identical piecewise-linear input.
TEST(Convergence, StickSlipOneMillisecondMatchesTenMicrosecondsOnLorrySignal) {
  const auto signal = test::make_lorry_signal(2024, kLorryRms);
  const double dt_coarse = 1e-3;
  const auto coarse = signal.sample(dt_coarse, 120001);  // 120 s
  const LorryResult a = run_lorry(coarse, dt_coarse, 1);
  const LorryResult b = run_lorry(coarse, dt_coarse, 100);
  const double t_rel = std::fabs(a.transmissibility / b.transmissibility - 1.0);
  const double p_abs = std::fabs(a.stick_probability - b.stick_probability);
  CHECK_TEXT(t_rel < 1e-3, StringFromFormat("T_ax %.6f vs %.6f: rel. diff %.3e", a.transmissibility,
                                            b.transmissibility, t_rel)
                               .asCharString());
  CHECK_TEXT(p_abs < 5e-3, StringFromFormat("p %.6f vs %.6f: diff %.3e", a.stick_probability,
                                            b.stick_probability, p_abs)
                               .asCharString());
  // The scene must be a real stick-slip one, not a trivially stuck or free seat.
  CHECK(a.stick_probability > 0.2 && a.stick_probability < 0.95);
  CHECK(a.transmissibility > 0.1);
  CHECK_EQUAL(0u, a.budget_exhausted);
  CHECK_EQUAL(0u, b.budget_exhausted);
  test::note_margin("lorry T_ax rel. diff 1 ms vs 1e-5 s", t_rel, 1e-3);
  test::note_margin("lorry p abs. diff 1 ms vs 1e-5 s", p_abs, 5e-3);
  test::note_margin("lorry T_ax", a.transmissibility, 0.0);
  test::note_margin("lorry p", a.stick_probability, 0.0);
}
