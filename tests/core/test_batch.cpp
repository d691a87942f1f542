// StickSlipBatch and BatchStatistics: every lane is a single Oscillator<T, CoulombStickSlip> (and
// RunningStatistics) with the same parameters and inputs, bit for bit, over scenes with many
// stick, break-away and reversal events; no heap.
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/metrics/batch_statistics.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/batch.hpp"
#include "support/allocation_counter.hpp"

using namespace stickslip;

namespace {

constexpr std::size_t kLanes = 8;
constexpr double kDtS = 1e-3;
constexpr std::size_t kSteps = 60000;  // 60 s

// Eight different seats: friction from K ~ 0.3 to ~1.8 (F_fs >= F_fk), masses, springs and
// dampers around the reference (b = 0 included), and every integrator.
OscillatorParams lane_params(std::size_t lane) {
  const Integrator integrators[] = {Integrator::exact,      Integrator::rk4,   Integrator::exact,
                                    Integrator::symplectic, Integrator::exact, Integrator::euler,
                                    Integrator::exact,      Integrator::rk4};
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, integrators[lane], kDtS);
  const double l = static_cast<double>(lane);
  p.kinetic_friction_n = 10.0 + 7.0 * l;
  p.static_friction_n = p.kinetic_friction_n * (1.0 + 0.05 * l);
  p.mass_kg = test::kMassKg * (0.8 + 0.05 * l);
  p.stiffness_n_per_m = test::kStiffnessNPerM * (1.2 - 0.05 * l);
  p.damping_ns_per_m = lane == 2 ? 0.0 : test::kDampingNsPerM * (0.6 + 0.1 * l);
  return p;
}

// A lorry-like input per lane (its own phases), sampled at dt.
template <typename T>
std::vector<std::vector<T>> lane_inputs(double rms_m_per_s2) {
  std::vector<std::vector<T>> inputs(kLanes);
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    const std::vector<double> a =
        test::make_lorry_signal(100 + lane, rms_m_per_s2).sample(kDtS, kSteps + 1);
    inputs[lane].assign(a.begin(), a.end());
  }
  return inputs;
}

template <typename T>
bool same_output(const StepOutput<T>& a, const StepOutput<T>& b) {
  return test::same_bits(a.x_r_m, b.x_r_m) && test::same_bits(a.v_r_m_per_s, b.v_r_m_per_s) &&
         test::same_bits(a.a_x_m_per_s2, b.a_x_m_per_s2) &&
         test::same_bits(a.friction_n, b.friction_n) &&
         test::same_bits(a.stuck_time_s, b.stuck_time_s) &&
         test::same_bits(a.stuck_fraction, b.stuck_fraction) && a.stuck == b.stuck &&
         a.events == b.events;
}

struct Comparison {
  long mismatched_steps = 0;
  long first_mismatch = -1;
  std::size_t first_lane = 0;
  long events[kLanes] = {};
  long stuck_steps[kLanes] = {};
};

// Steps the batch and one single oscillator per lane on the same inputs, comparing every output.
template <typename T>
Comparison run_against_singles(StickSlipBatch<T, kLanes>& batch,
                               Oscillator<T, CoulombStickSlip> (&single)[kLanes],
                               const std::vector<std::vector<T>>& inputs) {
  Comparison c;
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    const OscillatorParams p = lane_params(lane);
    const auto configured = batch.configure(lane, p);
    CHECK_TEXT(configured.ok(), configured.message.c_str());
    CHECK(single[lane].configure(p).ok());
    batch.reset(lane, T(0), T(0), inputs[lane][0]);
    single[lane].reset(T(0), T(0), inputs[lane][0]);
  }
  for (std::size_t n = 1; n <= kSteps; ++n) {
    T a_u[kLanes];
    for (std::size_t lane = 0; lane < kLanes; ++lane) a_u[lane] = inputs[lane][n];
    batch.step(a_u);
    bool all_same = true;
    for (std::size_t lane = 0; lane < kLanes; ++lane) {
      const StepOutput<T> expected = single[lane].step(a_u[lane]);
      c.events[lane] += expected.events;
      c.stuck_steps[lane] += expected.stuck ? 1 : 0;
      if (!same_output(batch.output(lane), expected)) {
        if (c.first_mismatch < 0) {
          c.first_mismatch = static_cast<long>(n);
          c.first_lane = lane;
        }
        all_same = false;
      }
    }
    if (!all_same) ++c.mismatched_steps;
  }
  return c;
}

template <typename T>
void check_lanes_equal_singles() {
  const auto inputs = lane_inputs<T>(0.5);
  static StickSlipBatch<T, kLanes> batch;  // static: about 19 kB, kept off the test's stack
  static Oscillator<T, CoulombStickSlip> single[kLanes];
  const Comparison c = run_against_singles(batch, single, inputs);
  CHECK_TEXT(c.mismatched_steps == 0,
             StringFromFormat("%ld steps differ, first at step %ld lane %zu", c.mismatched_steps,
                              c.first_mismatch, c.first_lane)
                 .asCharString());
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    // Every lane sticks and slips, with many events (so the event path ran in every lane).
    CHECK_TEXT(c.events[lane] > 200 && c.stuck_steps[lane] > 500 &&
                   c.stuck_steps[lane] < static_cast<long>(kSteps) - 500,
               StringFromFormat("lane %zu: %ld events, %ld stuck steps", lane, c.events[lane],
                                c.stuck_steps[lane])
                   .asCharString());
    CHECK_EQUAL(single[lane].event_budget_exhausted(), batch.lane(lane).event_budget_exhausted());
  }
}

}  // namespace

TEST_GROUP(Batch){};

// Double: eight seats with different parameters and integrators, each on its own lorry-like
// input (60 s, 250-400 events and 5-65 % of the time stuck per lane): every output of every step
// equals the single oscillator's.
TEST(Batch, EveryLaneEqualsASingleOscillatorBitForBitInDouble) {
  check_lanes_equal_singles<double>();
}

TEST(Batch, EveryLaneEqualsASingleOscillatorBitForBitInFloat) {
  check_lanes_equal_singles<float>();
}

// A lane count that is not a multiple of any vector width (the loop's remainder runs scalar):
// five seats over 20 s, bit for bit.
TEST(Batch, OddLaneCountEqualsSingleOscillators) {
  constexpr std::size_t kOdd = 5;
  const auto inputs = lane_inputs<double>(0.5);
  static StickSlipBatch<double, kOdd> batch;
  static Oscillator<double, CoulombStickSlip> single[kOdd];
  for (std::size_t lane = 0; lane < kOdd; ++lane) {
    CHECK(batch.configure(lane, lane_params(lane + 3)).ok());
    CHECK(single[lane].configure(lane_params(lane + 3)).ok());
    batch.reset(lane, 0.0, 0.0, inputs[lane][0]);
    single[lane].reset(0.0, 0.0, inputs[lane][0]);
  }
  long differences = 0, events = 0;
  for (std::size_t n = 1; n <= 20000; ++n) {
    double a_u[kOdd];
    for (std::size_t lane = 0; lane < kOdd; ++lane) a_u[lane] = inputs[lane][n];
    batch.step(a_u);
    for (std::size_t lane = 0; lane < kOdd; ++lane) {
      const StepOutput<double> expected = single[lane].step(a_u[lane]);
      events += expected.events;
      if (!same_output(batch.output(lane), expected)) ++differences;
    }
  }
  LONGS_EQUAL(0, differences);
  CHECK(events > 300);
}

// One input sample for all lanes (a sweep over parameters on one recording) is the same as
// passing that sample in every element of the array.
TEST(Batch, SharedInputEqualsTheSameSampleInEveryLane) {
  const std::vector<double> input = test::make_lorry_signal(7, 0.35).sample(kDtS, kSteps + 1);
  static StickSlipBatch<double, kLanes> shared, per_lane;
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    CHECK(shared.configure(lane, lane_params(lane)).ok());
    CHECK(per_lane.configure(lane, lane_params(lane)).ok());
    shared.reset(lane, 0.0, 0.0, input[0]);
    per_lane.reset(lane, 0.0, 0.0, input[0]);
  }
  long differences = 0, events = 0;
  for (std::size_t n = 1; n <= kSteps; ++n) {
    double all[kLanes];
    for (double& a : all) a = input[n];
    shared.step(input[n]);
    per_lane.step(all);
    for (std::size_t lane = 0; lane < kLanes; ++lane) {
      if (!same_output(shared.output(lane), per_lane.output(lane))) ++differences;
      events += shared.events(lane);
    }
  }
  LONGS_EQUAL(0, differences);
  CHECK(events > 1000);
}

// A NaN or infinite sample in one lane is replaced by that lane's previous sample and counted in
// that lane only, as the single oscillator does; the other lanes are untouched.
TEST(Batch, NonFiniteInputIsReplacedInItsLaneOnly) {
  const auto inputs = lane_inputs<double>(0.5);
  static StickSlipBatch<double, kLanes> batch;
  static Oscillator<double, CoulombStickSlip> single[kLanes];
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    CHECK(batch.configure(lane, lane_params(lane)).ok());
    CHECK(single[lane].configure(lane_params(lane)).ok());
    batch.reset(lane, 0.0, 0.0, inputs[lane][0]);
    single[lane].reset(0.0, 0.0, inputs[lane][0]);
  }
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  long differences = 0;
  for (std::size_t n = 1; n <= 3000; ++n) {
    double a_u[kLanes];
    for (std::size_t lane = 0; lane < kLanes; ++lane) a_u[lane] = inputs[lane][n];
    if (n % 100 == 0) a_u[3] = bad[(n / 100) % 3];  // lane 3 only, 30 times
    if (n == 1500) a_u[6] = bad[0];
    batch.step(a_u);
    for (std::size_t lane = 0; lane < kLanes; ++lane) {
      if (!same_output(batch.output(lane), single[lane].step(a_u[lane]))) ++differences;
    }
  }
  LONGS_EQUAL(0, differences);
  CHECK_EQUAL(30u, batch.lane(3).rejected_inputs());
  CHECK_EQUAL(1u, batch.lane(6).rejected_inputs());
  CHECK_EQUAL(0u, batch.lane(0).rejected_inputs());
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    CHECK_EQUAL(single[lane].rejected_inputs(), batch.lane(lane).rejected_inputs());
    CHECK(std::isfinite(batch.x_r(lane)) && std::isfinite(batch.a_x(lane)));
  }
}

// Each lane's statistics equal a RunningStatistics fed with that lane's samples (more than one
// 256-sample block, so the folding into the compensated totals is compared too).
TEST(Batch, StatisticsOfEveryLaneEqualRunningStatistics) {
  const auto inputs = lane_inputs<double>(0.5);
  static StickSlipBatch<double, kLanes> batch;
  BatchStatistics<double, kLanes> stats;
  RunningStatistics<double> single_stats[kLanes];
  stats.reset();
  double a_u[kLanes];
  double a_x[kLanes];
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    CHECK(batch.configure(lane, lane_params(lane)).ok());
    batch.reset(lane, 0.0, 0.0, inputs[lane][0]);
    a_u[lane] = inputs[lane][0];
    a_x[lane] = batch.lane(lane).current().a_x_m_per_s2;
    single_stats[lane].reset();
    single_stats[lane].add_sample(a_u[lane], a_x[lane]);
  }
  stats.add_sample(a_u, a_x);
  for (std::size_t n = 1; n <= kSteps; ++n) {
    for (std::size_t lane = 0; lane < kLanes; ++lane) a_u[lane] = inputs[lane][n];
    batch.step(a_u);
    stats.add_sample(a_u, batch.a_x_array());
    stats.add_step(batch.stuck_fraction_array());
    for (std::size_t lane = 0; lane < kLanes; ++lane) {
      single_stats[lane].add_sample(a_u[lane], batch.a_x(lane));
      single_stats[lane].add_step(batch.stuck_fraction(lane));
    }
  }
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    const RunningStatistics<double> s = stats.lane(lane);
    const RunningStatistics<double>& r = single_stats[lane];
    CHECK(test::same_bits(r.rms_u(), s.rms_u()));
    CHECK(test::same_bits(r.rms_x(), s.rms_x()));
    CHECK(test::same_bits(r.transmissibility(), s.transmissibility()));
    CHECK(test::same_bits(r.stick_probability(), s.stick_probability()));
    CHECK_EQUAL(r.samples(), s.samples());
    CHECK_EQUAL(r.steps(), s.steps());
    CHECK(s.stick_probability() > 0.0 && s.stick_probability() < 1.0);
  }
}

// configure(), reset(), step() with events in every lane and the statistics: no heap.
TEST(Batch, RunsWithoutHeap) {
  const auto inputs = lane_inputs<double>(0.5);
  static StickSlipBatch<double, kLanes> batch;
  static BatchStatistics<double, kLanes> stats;
  long events = 0;
  test::start_counting_allocations();
  bool configured = true;
  for (std::size_t lane = 0; lane < kLanes; ++lane) {
    configured = configured && batch.configure(lane, lane_params(lane)).ok();
    batch.reset(lane, 0.0, 0.0, inputs[lane][0]);
  }
  stats.reset();
  for (std::size_t n = 1; n <= kSteps; ++n) {
    double a_u[kLanes];
    for (std::size_t lane = 0; lane < kLanes; ++lane) a_u[lane] = inputs[lane][n];
    batch.step(a_u);
    stats.add_sample(a_u, batch.a_x_array());
    stats.add_step(batch.stuck_fraction_array());
    for (std::size_t lane = 0; lane < kLanes; ++lane) events += batch.events(lane);
  }
  const auto seen = test::stop_counting_allocations();
  CHECK(configured);
  UNSIGNED_LONGS_EQUAL(0, seen.calls);
  CHECK(events > 1000);
}

// A lane accepts only the Coulomb stick-slip model, and says so by name; a refused lane keeps
// its previous configuration.
TEST(Batch, RefusesAnotherModelNamingIt) {
  static StickSlipBatch<double, 2> batch;
  CHECK(batch.configure(0, lane_params(0)).ok());
  OscillatorParams p = lane_params(1);
  p.model = FrictionModel::signum;
  const ConfigResult refused = batch.configure(1, p);
  CHECK(refused.status == Status::unsupported);
  STRCMP_CONTAINS("signum", refused.message.c_str());
  p = lane_params(1);
  p.dt_s = -1.0;
  CHECK(batch.configure(0, p).status == Status::out_of_range);
  batch.reset(0, 0.0, 0.0, 0.0);
  batch.step(1.0);
  CHECK(std::isfinite(batch.x_r(0)));
}
