// The state estimator against truth it did not make: an independent fine-step stick-slip seat
// (F_fk 60 N, F_fs 70 N, both rising 20 % over 100 s; the estimator starts at 45/45 N) on
// lorry-like floor input, through accelerometers with noise and bias and a quantised travel
// sensor (estimator_scenario.hpp). Several seeds and floor levels; tolerances are the targets.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "estimator_scenario.hpp"
#include "stickslip/observer/state_estimator.hpp"
#include "support/allocation_counter.hpp"

using namespace stickslip;
using namespace stickslip::test;

namespace {

constexpr std::uint64_t kSeeds[] = {1, 2, 3};

EstimatorErrors run_scenario(std::uint64_t seed, double floor_rms, Sensors sensors) {
  EstimatorScenario sc;
  sc.seed = seed;
  sc.floor_rms_m_per_s2 = floor_rms;
  return run_estimator<double>(make_scenario(sc), estimator_params(sc), sensors);
}

}  // namespace

TEST_GROUP(StateEstimator){};

TEST(StateEstimator, ConfigureRefusesNonPhysicalParametersNamingThem) {
  StateEstimator<double> estimator;
  StateEstimatorParams p;
  CHECK_TRUE(estimator.configure(p).ok());
  p.mass_kg = 0.0;
  ConfigResult r = estimator.configure(p);
  CHECK_TRUE(r.status == Status::out_of_range);
  STRCMP_CONTAINS("mass_kg", r.message.c_str());
  p = StateEstimatorParams{};
  p.travel_noise_m = std::nan("");
  r = estimator.configure(p);
  CHECK_TRUE(r.status == Status::not_finite);
  STRCMP_CONTAINS("travel_noise_m", r.message.c_str());
  p = StateEstimatorParams{};
  p.initial_static_friction_n = 30.0;  // below F_fk = 45 N
  r = estimator.configure(p);
  CHECK_FALSE(r.ok());
  STRCMP_CONTAINS("initial_static_friction_n", r.message.c_str());
  p = StateEstimatorParams{};
  p.travel_noise_m = 0.0;
  p.travel_resolution_m = 0.0;  // a perfect travel sensor: the update's variance would be 0
  CHECK_FALSE(estimator.configure(p).ok());
  p = StateEstimatorParams{};
  p.dt_s = 0.1;  // sqrt(k/m) dt = 1.14: more than one reversal per step possible
  CHECK_FALSE(estimator.configure(p).ok());
}

// Where the seat slips a good part of the time (K = 0.76 and 0.61 at the start); at floor RMS
// 0.35 (stuck 97 %) the target is not met: docs/IDENTIFICATION.md.
TEST(StateEstimator, WithTravelTracksRelativeVelocityWithinFivePercentOfItsRms) {
  for (double rms : {0.8, 1.0}) {
    for (std::uint64_t seed : kSeeds) {
      const EstimatorErrors e = run_scenario(seed, rms, Sensors::acceleration_and_travel);
      CHECK_TRUE(e.v_r_rms_relative < 0.05);
    }
  }
}

TEST(StateEstimator, WithTravelFrictionForceWithinTenPercentOfKineticAfterTenSeconds) {
  for (double rms : {0.35, 0.6, 1.0}) {
    for (std::uint64_t seed : kSeeds) {
      const EstimatorErrors e = run_scenario(seed, rms, Sensors::acceleration_and_travel);
      CHECK_TRUE(e.friction_rms_relative < 0.10);
    }
  }
}

// The truth's F_fk rises 20 % over the run; the estimate starts 25 % low.
TEST(StateEstimator, KineticFrictionEstimateTracksTwentyPercentDriftWithinFivePercent) {
  for (double rms : {0.6, 1.0}) {
    for (std::uint64_t seed : kSeeds) {
      const EstimatorErrors e = run_scenario(seed, rms, Sensors::acceleration_and_travel);
      CHECK_TRUE(e.kinetic_max_relative < 0.05);  // over t >= 20 s
      CHECK_TRUE(e.kinetic_convergence_s < 20.0);
    }
  }
}

// F_fs starts at 45 N against a truth of 70-84 N; learnt from the break-aways alone.
TEST(StateEstimator, StaticFrictionEstimateEndsWithinTenPercent) {
  for (double rms : {0.6, 1.0}) {
    for (std::uint64_t seed : kSeeds) {
      const EstimatorErrors e = run_scenario(seed, rms, Sensors::acceleration_and_travel);
      CHECK_TRUE(std::fabs(e.static_final_relative) < 0.10);
    }
  }
}

// Without a travel sensor the velocity and the friction still come out (the accelerometers and
// the friction law), and x_r stays within a fraction of the stick band F_fs/k (6-7 mm).
TEST(StateEstimator, AccelerationOnlyKeepsVelocityAndFrictionAndBoundsTravel) {
  for (std::uint64_t seed : kSeeds) {
    const EstimatorErrors e = run_scenario(seed, 1.0, Sensors::acceleration_only);
    CHECK_TRUE(e.v_r_rms_relative < 0.05);
    CHECK_TRUE(e.friction_rms_relative < 0.10);
    CHECK_TRUE(e.x_r_rms_m < 1e-3);
  }
}

// The stuck state the estimator reports agrees with the truth's on most samples.
TEST(StateEstimator, StuckStateAgreesWithTruthOnNinetyFivePercentOfSamples) {
  for (double rms : {0.35, 0.6, 1.0}) {
    const EstimatorErrors e = run_scenario(2, rms, Sensors::acceleration_and_travel);
    CHECK_TRUE(e.stuck_agreement > 0.95);
  }
}

// Float from the same source meets the same targets.
TEST(StateEstimator, FloatMeetsTheTargetsToo) {
  EstimatorScenario sc;
  sc.seed = 4;
  sc.floor_rms_m_per_s2 = 1.0;
  const EstimatorErrors e = run_estimator<float>(make_scenario(sc), estimator_params(sc),
                                                 Sensors::acceleration_and_travel);
  CHECK_TRUE(e.v_r_rms_relative < 0.05);
  CHECK_TRUE(e.friction_rms_relative < 0.10);
  CHECK_TRUE(e.kinetic_max_relative < 0.05);
}

// A seat parked on a quiet floor: stuck throughout, and the friction estimates do not move.
TEST(StateEstimator, FrictionEstimatesHoldWhileStuck) {
  static StateEstimator<double> estimator;
  CHECK_TRUE(estimator.configure(StateEstimatorParams{}).ok());
  estimator.reset(0.0);
  Gaussian noise(11);
  const double kinetic = estimator.estimate().kinetic_friction_n;
  const double fstatic = estimator.estimate().static_friction_n;
  for (int n = 0; n < 10000; ++n) {
    const double a_u = 0.1 * std::sin(0.0063 * n);  // 1 Hz, 0.1 m/s^2: load 8.8 N < 45 N
    const StateEstimate<double>& e =
        estimator.step(a_u + 0.02 * noise(), a_u + 0.02 * noise() + 0.01, 0.0);
    CHECK_TRUE(e.stuck);
    CHECK_EQUAL(kinetic, e.kinetic_friction_n);
    CHECK_EQUAL(fstatic, e.static_friction_n);
    CHECK_EQUAL(0.0, e.v_r_m_per_s);
  }
}

// A non-finite floor sample is replaced and counted; a non-finite measurement is "not measured".
TEST(StateEstimator, NonFiniteSamplesNeverReachTheOutputs) {
  static StateEstimator<double> estimator;
  CHECK_TRUE(estimator.configure(StateEstimatorParams{}).ok());
  estimator.reset(0.0);
  const double nan = std::nan("");
  const double inf = HUGE_VAL;
  const double inputs[][3] = {{nan, 0.0, 0.0}, {inf, nan, nan}, {0.5, inf, -inf}, {2.0, nan, 0.0}};
  for (int round = 0; round < 100; ++round) {
    for (const auto& in : inputs) {
      const StateEstimate<double>& e = estimator.step(in[0], in[1], in[2]);
      CHECK_TRUE(std::isfinite(e.x_r_m) && std::isfinite(e.v_r_m_per_s));
      CHECK_TRUE(std::isfinite(e.friction_n) && std::isfinite(e.kinetic_friction_n));
    }
  }
  CHECK_EQUAL(200u, estimator.rejected_inputs());
}

TEST(StateEstimator, StepDoesNotAllocate) {
  EstimatorScenario sc;
  sc.duration_s = 5.0;
  sc.floor_rms_m_per_s2 = 1.0;
  const std::vector<ScenarioSample> samples = make_scenario(sc);
  static StateEstimator<float> estimator;
  CHECK_TRUE(estimator.configure(estimator_params(sc)).ok());
  estimator.reset(float(samples[0].a_u));
  start_counting_allocations();
  std::uint32_t breakaways = 0;
  for (std::size_t n = 1; n < samples.size(); ++n) {
    const ScenarioSample& s = samples[n];
    breakaways = estimator.step(float(s.a_u), float(s.a_x), float(s.x_r_measured)).breakaways;
  }
  const AllocationCount seen = stop_counting_allocations();
  CHECK_EQUAL(0u, seen.calls);
  CHECK_TRUE(breakaways > 10);  // the run went through the event paths
}
