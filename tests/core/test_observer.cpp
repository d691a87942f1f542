// The stick-slip observer: model state, windowed statistics, regime with hysteresis, measured-seat
// residual and mismatch flag, no heap.
#include <cmath>
#include <cstddef>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/observer/observer.hpp"
#include "support/allocation_counter.hpp"

using namespace stickslip;

namespace {

constexpr double kDt = 1e-3;

ObserverParams observer_params(double friction_n, double window_s = 2.0) {
  ObserverParams p;
  p.model = test::reference_params(FrictionModel::stick_slip, Integrator::exact, kDt);
  p.model.kinetic_friction_n = p.model.static_friction_n = friction_n;
  p.window_s = window_s;
  p.exponential_time_s = 2.0;
  p.mismatch_rms_m_per_s2 = 0.05;
  return p;
}

std::vector<double> lorry(std::size_t count, double rms = 0.35, std::uint64_t seed = 5) {
  return test::make_lorry_signal(seed, rms).sample(kDt, count);
}

}  // namespace

TEST_GROUP(Observer){};

// The observer's estimate is the model's step, bit for bit: it adds figures, never changes the
// state.
TEST(Observer, EstimateIsTheModelStepBitForBit) {
  const std::vector<double> a = lorry(20001);
  static Observer<double, CoulombStickSlip> observer;
  Oscillator<double, CoulombStickSlip> seat;
  const ObserverParams p = observer_params(30.0);
  CHECK_TRUE(observer.configure(p).ok());
  CHECK_TRUE(seat.configure(p.model).ok());
  observer.reset(a[0]);
  seat.reset(0.0, 0.0, a[0]);
  int stuck_steps = 0;
  for (std::size_t n = 1; n < a.size(); ++n) {
    const StepOutput<double> want = seat.step(a[n]);
    const ObserverEstimate<double>& got = observer.update(a[n]);
    CHECK_EQUAL(want.x_r_m, got.model.x_r_m);
    CHECK_EQUAL(want.v_r_m_per_s, got.model.v_r_m_per_s);
    CHECK_EQUAL(want.a_x_m_per_s2, got.model.a_x_m_per_s2);
    CHECK_EQUAL(want.friction_n, got.model.friction_n);
    CHECK_EQUAL(want.stuck, got.model.stuck);
    stuck_steps += want.stuck ? 1 : 0;
  }
  CHECK_TRUE(stuck_steps > 1000);  // the scene really exercises the stick-slip paths
}

// The block window's figures equal a recomputation over the last window of samples, and its
// stick/slip event counts equal the stuck-flag transitions counted from outside.
TEST(Observer, WindowFiguresEqualARecomputationOverTheLastWindow) {
  const std::size_t count = 12001;  // 12 s; window 2 s = 10 blocks of 200 samples
  const std::vector<double> a = lorry(count, 0.35, 9);
  static Observer<double, CoulombStickSlip> observer;
  CHECK_TRUE(observer.configure(observer_params(30.0)).ok());
  observer.reset(a[0]);
  std::vector<double> a_x(count), stuck_fraction(count);
  std::vector<int> stuck(count);
  stuck[0] = observer.estimate().model.stuck ? 1 : 0;
  for (std::size_t n = 1; n < count; ++n) {
    const ObserverEstimate<double>& e = observer.update(a[n]);
    a_x[n] = e.model.a_x_m_per_s2;
    stuck_fraction[n] = e.model.stuck_fraction;
    stuck[n] = e.model.stuck ? 1 : 0;
  }
  // 12000 updates = 60 complete blocks; the window holds updates 10001..12000.
  const ObserverSummary s = observer.summary();
  CHECK_TRUE(s.window_full);
  DOUBLES_EQUAL(2.0, s.window_s, 1e-12);
  double u_sq = 0, x_sq = 0, stuck_time = 0;
  unsigned stick_events = 0, slip_events = 0;
  for (std::size_t n = 10001; n <= 12000; ++n) {
    u_sq += a[n] * a[n];
    x_sq += a_x[n] * a_x[n];
    stuck_time += stuck_fraction[n];
    stick_events += (stuck[n] && !stuck[n - 1]) ? 1u : 0u;
    slip_events += (!stuck[n] && stuck[n - 1]) ? 1u : 0u;
  }
  const double rms_u = std::sqrt(u_sq / 2000), rms_x = std::sqrt(x_sq / 2000);
  DOUBLES_EQUAL(rms_u, s.rms_u_m_per_s2, 1e-12 * rms_u);
  DOUBLES_EQUAL(rms_x, s.rms_x_m_per_s2, 1e-12 * rms_x);
  DOUBLES_EQUAL(rms_x / rms_u, s.transmissibility, 1e-12);
  DOUBLES_EQUAL(stuck_time / 2000, s.stick_probability, 1e-12);
  DOUBLES_EQUAL(den_hartog_factor(30.0, test::kMassKg, rms_u), s.den_hartog_k, 1e-12);
  CHECK_EQUAL(stick_events, s.stick_events);
  CHECK_EQUAL(slip_events, s.slip_events);
  CHECK_TRUE(stick_events > 5);
}

// The regime follows K of the window: a rough road (small K) says signum suffices; when the road
// turns smooth (large K) the regime moves to stick-slip required, once, without flicker.
TEST(Observer, RegimeFollowsTheRoadWithoutFlicker) {
  static Observer<double, CoulombStickSlip> observer;
  CHECK_TRUE(observer.configure(observer_params(20.0)).ok());
  const std::vector<double> rough = lorry(20001, 1.2, 3);    // K = 4*20/(pi sqrt2 88.4 1.2) ~ 0.17
  const std::vector<double> smooth = lorry(20001, 0.15, 4);  // K ~ 1.36
  observer.reset(rough[0]);
  for (std::size_t n = 1; n < rough.size(); ++n) observer.update(rough[n]);
  CHECK_TRUE(observer.summary().regime_known);
  CHECK_TRUE(observer.regime() == FrictionRegime::signum_suffices);
  for (std::size_t n = 0; n < smooth.size(); ++n) observer.update(smooth[n]);
  const ObserverSummary s = observer.summary();
  CHECK_TRUE(observer.regime() == FrictionRegime::stick_slip_required);
  CHECK_TRUE(s.stick_probability > 0.5);
  // signum -> (transition) -> stick-slip: at most two changes over 40 s with 200 K updates.
  CHECK_TRUE(s.regime_changes >= 1 && s.regime_changes <= 2);
}

// K wandering around a boundary by less than the hysteresis never changes the regime; a real
// crossing does, once.
TEST(Observer, HysteresisHoldsTheRegimeNearABoundary) {
  RegimeTracker tracker;
  tracker.configure(0.05);
  CHECK_TRUE(tracker.update(0.30) == FrictionRegime::signum_suffices);
  for (int i = 0; i < 100; ++i) tracker.update(i % 2 ? 0.37 : 0.44);  // 0.4 +- 0.04
  CHECK_TRUE(tracker.regime() == FrictionRegime::signum_suffices);
  CHECK_EQUAL(0u, tracker.changes());
  tracker.update(0.46);
  CHECK_TRUE(tracker.regime() == FrictionRegime::transition);
  for (int i = 0; i < 100; ++i) tracker.update(i % 2 ? 0.37 : 0.72);
  CHECK_TRUE(tracker.regime() == FrictionRegime::transition);
  tracker.update(0.81);
  CHECK_TRUE(tracker.regime() == FrictionRegime::stick_slip_required);
  tracker.update(0.34);
  CHECK_TRUE(tracker.regime() == FrictionRegime::signum_suffices);
  CHECK_EQUAL(3u, tracker.changes());
}

// A measured seat acceleration from the same physics leaves no residual, and the friction force
// recovered from it is the model's; from a seat with three times the friction the residual grows
// and the mismatch flag is raised.
TEST(Observer, MeasuredSeatGivesResidualFrictionEstimateAndMismatchFlag) {
  const std::vector<double> a = lorry(10001, 0.35, 11);
  for (const double seat_friction_n : {30.0, 90.0}) {
    static Observer<double, CoulombStickSlip> observer;
    Oscillator<double, CoulombStickSlip> seat;  // plays the real seat with its sensor
    CHECK_TRUE(observer.configure(observer_params(30.0)).ok());
    CHECK_TRUE(seat.configure(observer_params(seat_friction_n).model).ok());
    observer.reset(a[0]);
    seat.reset(0.0, 0.0, a[0]);
    double max_friction_error = 0.0;
    for (std::size_t n = 1; n < a.size(); ++n) {
      const double measured = seat.step(a[n]).a_x_m_per_s2;
      const ObserverEstimate<double>& e = observer.update(a[n], measured);
      CHECK_TRUE(e.measured);
      max_friction_error =
          std::fmax(max_friction_error, std::fabs(e.measured_friction_n - e.model.friction_n));
    }
    const ObserverSummary s = observer.summary();
    if (seat_friction_n == 30.0) {
      DOUBLES_EQUAL(0.0, s.residual_rms_m_per_s2, 0.0);
      CHECK_TRUE(max_friction_error < 1e-9);  // N: rounding of -m a_x - k x_r - b v_r
      CHECK_FALSE(s.model_mismatch);
    } else {
      CHECK_TRUE(s.residual_rms_m_per_s2 > 0.05);
      CHECK_TRUE(s.model_mismatch);
      CHECK_TRUE(observer.model_mismatch());
    }
  }
}

// A measured value that is not a number is not used: the sample counts as unmeasured.
TEST(Observer, NonFiniteMeasurementIsNotUsed) {
  static Observer<float, CoulombStickSlip> observer;
  CHECK_TRUE(observer.configure(observer_params(30.0)).ok());
  observer.reset(0.0f);
  const ObserverEstimate<float>& e = observer.update(0.1f, NAN);
  CHECK_FALSE(e.measured);
  CHECK_EQUAL(0.0f, e.residual_m_per_s2);
}

TEST(Observer, ConfigureNamesTheBadParameter) {
  static Observer<double, CoulombStickSlip> observer;
  ObserverParams p = observer_params(30.0);
  p.window_s = 0.005;  // 5 samples for 10 blocks
  ConfigResult r = observer.configure(p);
  CHECK_FALSE(r.ok());
  STRCMP_CONTAINS("window_s", r.message.c_str());
  p = observer_params(30.0);
  p.regime_hysteresis_k = 0.3;
  r = observer.configure(p);
  STRCMP_CONTAINS("regime_hysteresis_k", r.message.c_str());
  p = observer_params(30.0);
  p.model.mass_kg = -1.0;
  r = observer.configure(p);
  STRCMP_CONTAINS("mass_kg", r.message.c_str());
}

// configure, reset and 10 s of updates with measurements, and the summary: no heap.
TEST(Observer, UsesNoHeap) {
  const std::vector<double> a = lorry(10001);
  static Observer<double, CoulombStickSlip> observer;
  test::start_counting_allocations();
  const bool ok = observer.configure(observer_params(30.0)).ok();
  observer.reset(a[0]);
  for (std::size_t n = 1; n < a.size(); ++n) observer.update(a[n], 0.9 * a[n]);
  volatile double sink = observer.summary().transmissibility + observer.comfort().seat_vdv();
  (void)sink;
  const auto seen = test::stop_counting_allocations();
  CHECK_TRUE(ok);
  UNSIGNED_LONGS_EQUAL(0, seen.calls);
}

// A slow sweep of K from 0.2 to 1.1 (the road getting smoother): the regime changes exactly twice,
// each time as soon as the window's K has passed the documented threshold plus the hysteresis
// (0.4 + 0.05, then 0.75 + 0.05), and never flickers back.
TEST(Observer, RegimeChangesAtTheDocumentedThresholdsOnAKSweep) {
  const double friction_n = 20.0, duration_s = 300.0;
  ObserverParams p = observer_params(friction_n, 10.0);
  static Observer<double, CoulombStickSlip> observer;
  CHECK_TRUE(observer.configure(p).ok());
  const auto count = static_cast<std::size_t>(duration_s / kDt) + 1;
  const test::LorrySignal road = test::make_lorry_signal(21, 1.0);
  // K(t) = K0 / g(t) for a_u = g(t) * road(t) with RMS(road) = 1: g = K0 / K_target(t).
  const double k_at_unit_rms = den_hartog_factor(friction_n, p.model.mass_kg, 1.0);
  const auto gain = [&](double t) { return k_at_unit_rms / (0.2 + 0.9 * t / duration_s); };
  observer.reset(gain(0.0) * road.at(0.0));
  std::uint32_t changes = 0;
  double k_at_change[4] = {};
  FrictionRegime regime_after[4] = {};
  for (std::size_t n = 1; n < count; ++n) {
    const double t = static_cast<double>(n) * kDt;
    observer.update(gain(t) * road.at(t));
    if (n % 1000 == 0) {  // a block completes every second
      const ObserverSummary s = observer.summary();
      if (s.regime_changes != changes && changes < 4) {
        k_at_change[changes] = s.den_hartog_k;
        regime_after[changes] = s.regime;
        changes = s.regime_changes;
      }
    }
  }
  CHECK_EQUAL(2u, changes);
  CHECK_TRUE(regime_after[0] == FrictionRegime::transition);
  CHECK_TRUE(regime_after[1] == FrictionRegime::stick_slip_required);
  // K grows by about 0.003 per second here; the window's K fluctuates with the road by a few %.
  CHECK_TRUE(k_at_change[0] > kSignumSufficesBelowK + 0.05 && k_at_change[0] < 0.5);
  CHECK_TRUE(k_at_change[1] > kStickSlipRequiredAboveK + 0.05 && k_at_change[1] < 0.86);
}

// With end stops (kEndStops) the estimate is EndStopOscillator's step, bit for bit, through
// contacts; the friction measured from the seat's acceleration takes off the stop's force, so a
// measurement equal to the model's a_x gives back the model's friction force while slipping.
TEST(Observer, EndStopObserverEstimateIsTheEndStopModelsStep) {
  const std::vector<double> a = lorry(20001, 4.0);
  static Observer<double, CoulombStickSlip, 10, true, true> observer;
  EndStopOscillator<double, CoulombStickSlip> seat;
  ObserverParams p = observer_params(30.0);
  p.stops.travel_m = 0.02;
  CHECK_TRUE(observer.configure(p).ok());
  CHECK_TRUE(seat.configure(p.model, p.stops).ok());
  observer.reset(a[0]);
  seat.reset(0.0, 0.0, a[0]);
  int contact_slips = 0;
  for (std::size_t n = 1; n < a.size(); ++n) {
    const StepOutput<double> want = seat.step(a[n]);
    const ObserverEstimate<double>& got = observer.update(a[n], want.a_x_m_per_s2);
    CHECK_EQUAL(want.x_r_m, got.model.x_r_m);
    CHECK_EQUAL(want.v_r_m_per_s, got.model.v_r_m_per_s);
    CHECK_EQUAL(want.a_x_m_per_s2, got.model.a_x_m_per_s2);
    CHECK_EQUAL(want.friction_n, got.model.friction_n);
    CHECK_EQUAL(want.stuck, got.model.stuck);
    if (!want.stuck && seat.contact() != 0) {
      ++contact_slips;
      // m a_x + k x + b v + F_stop + F_f = 0 while slipping, rounded in each of its five terms
      // (forces of up to a few kN at the stops): 1e-9 N.
      DOUBLES_EQUAL(want.friction_n, got.measured_friction_n, 1e-9);
    }
  }
  CHECK_TRUE(seat.contacts() > 10);
  CHECK_EQUAL(seat.contacts(), observer.model().contacts());
  CHECK_TRUE(contact_slips > 100);
}
