// The trip counts that the static bound of a step takes per step or per call rather than per
// entry (port/baremetal/loop-bounds.json, tools/elf-wcet.py "per_call"), counted by laws that
// declare count_loop_run() (step_common.hpp), on random seats and floors that reach them:
//   - slip()'s block walk (Oscillator): at most 2^(L+1) - 1 runs of its body per step over all its
//     calls, a run that returns an event included (event_search.hpp), and exactly 1 for L = 0,
//     the firmware's plan, in the steps with several events too;
//   - the searches of a tick's polynomial for v_r = 0 (Oscillator, first_crossing()): at most
//     kEventBudget / 2 + 2^L per step, reached at L = 0 (2: the first pass's and one slip from
//     rest against the way F_L moves), in double, float and Q7.24, and none in a step whose one
//     event is a break-away (its slip goes with F_L and cannot return to rest);
//   - the end-stop scan (EndStopOscillator::move_to_mode_end()): at most 16 blocks per call over
//     its two scans together, the runs that leave the mode included, its dip bisection at most
//     kEventLevels - 4 = 12 halvings per call, and at most 2 ticks it solves itself per call
//     (the rest of its start's tick and a dip's), all reached.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/integrators/step_map.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_oscillator.hpp"

using namespace stickslip;

namespace {

struct LoopTally {
  long walk = 0;         // block-walk runs in the current step
  long tick_search = 0;  // searches of a tick's polynomial in the current step
  long scan = 0;         // scan runs in the current move_to_mode_end() call
  long dip = 0;          // dip halvings in the current call
  long ticks = 0;        // ticks the current call solves itself
  long most_ticks = 0;
  long scan_after_dip = 0;
  long most_scan = 0, most_dip = 0;
  long calls_with_a_second_scan = 0, most_scan_with_a_second_scan = 0;

  void end_call() {
    most_scan = std::max(most_scan, scan);
    most_dip = std::max(most_dip, dip);
    most_ticks = std::max(most_ticks, ticks);
    if (scan_after_dip > 0) {
      ++calls_with_a_second_scan;
      most_scan_with_a_second_scan = std::max(most_scan_with_a_second_scan, scan);
    }
    scan = dip = scan_after_dip = ticks = 0;
  }
};

LoopTally tally;

template <typename Law>
struct Counting : Law {
  static void count_loop_run(LoopRun run) noexcept {
    switch (run) {
      case LoopRun::block_walk:
        ++tally.walk;
        break;
      case LoopRun::tick_search:
        ++tally.tick_search;
        break;
      case LoopRun::mode_search:
        tally.end_call();
        break;
      case LoopRun::scan_block:
        ++tally.scan;
        if (tally.dip > 0) ++tally.scan_after_dip;
        break;
      case LoopRun::dip_bisection:
        ++tally.dip;
        break;
      case LoopRun::mode_tick:
        ++tally.ticks;
        break;
    }
  }
};

struct WalkTally {
  long most_per_step = 0;
  long steps_with_several_events = 0;
  long steps_over_bound = 0;
  long most_searches_at_level_0 = 0;  // tick searches in one step at L = 0
  long steps_over_search_bound = 0;
  long most_searches_q724 = 0;
};

// A random seat: m 40-140 kg, k 3e3-1e5 N/m, damped or not, F_fs up to 1.5 F_fk, its step set by
// omega0 dt in (0.01, 1.5), so that the plan's level L runs from 0 up.
OscillatorParams random_seat(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  OscillatorParams p;
  p.mass_kg = 40.0 + 100.0 * u(rng);
  p.stiffness_n_per_m = 3e3 * std::pow(10.0, 1.5 * u(rng));
  p.damping_ns_per_m = n % 2 == 0 ? 0.0 : 2000.0 * u(rng);
  p.kinetic_friction_n = 5.0 + 60.0 * u(rng);
  p.static_friction_n = p.kinetic_friction_n * (1.0 + 0.5 * u(rng));
  p.dt_s = (0.01 + 1.49 * u(rng)) / std::sqrt(p.stiffness_n_per_m / p.mass_kg);
  p.integrator = Integrator::exact;
  return p;
}

// White noise (a new level every sample) or a random phase each sample: F_L jumps by several
// F_fs from step to step, so that steps hold several events.
std::vector<double> hostile_floor(std::mt19937_64& rng, int n, std::size_t samples) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double level = 1.0 + 40.0 * u(rng);
  std::vector<double> a(samples);
  for (double& x : a)
    x = n % 3 == 0 ? level * (2.0 * u(rng) - 1.0) : level * std::sin(6.3 * u(rng));
  return a;
}

// The most tick searches one step makes: one per pass that slips from rest against the way F_L
// moves and right after no such pass that searched (one in two of the passes below the budget;
// the first pass starts at the step's start, not a slip's, and the pass past the budget
// searches nothing), and at most one per tick in the block walks, which move on past a tick
// searched.
template <typename Model>
long tick_search_bound(int level) {
  return Model::kEventBudget / 2 + (1L << level);
}

template <typename T, typename Law>
void walk_runs(const OscillatorParams& p, const std::vector<double>& floor, WalkTally& out,
               int& level) {
  using Model = Oscillator<T, Counting<Law>>;
  Model seat;
  CHECK_TRUE(seat.configure(p).ok());
  level = seat.event_search().tick_level;
  const long bound = (2L << level) - 1;
  const long searches = tick_search_bound<Model>(level);
  for (double a : floor) {
    tally.walk = tally.tick_search = 0;
    const StepOutput<T> out_step = seat.step(static_cast<T>(a));
    if (tally.walk > bound) ++out.steps_over_bound;
    if (tally.tick_search > searches) ++out.steps_over_search_bound;
    if (level == 0) out.most_per_step = std::max(out.most_per_step, tally.walk);
    if (level == 0 && out_step.events >= 2) ++out.steps_with_several_events;
    if (level == 0 && Model::kEventBudget == kMaxEventsOfTheExactSolutionPerStep)
      out.most_searches_at_level_0 = std::max(out.most_searches_at_level_0, tally.tick_search);
  }
}

// Q7.24 in scene units: one tick per step (L = 0), its cubic searched by every pass that slips
// in direction, the first included. The firmware's ranges (+-32.768 m/s^2, 0.1 m), the floor
// clipped to them, and friction of at least 30 N, which Q7.24 resolves in those units.
template <typename Law>
void q724_runs(OscillatorParams p, const std::vector<double>& floor, WalkTally& out) {
  p.input_range_m_per_s2 = 32.768;
  p.displacement_range_m = 0.1;
  p.kinetic_friction_n = std::max(p.kinetic_friction_n, 30.0);
  p.static_friction_n = std::max(p.static_friction_n, p.kinetic_friction_n);
  ScaledOscillator<Fixed32, Counting<Law>> seat;
  const ConfigResult configured = seat.configure(p);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  const long searches = tick_search_bound<Oscillator<Fixed32, Counting<Law>>>(0);
  const double a_unit = seat.units().acceleration_m_per_s2();
  for (double a : floor) {
    tally.tick_search = 0;
    seat.step(Fixed32(std::clamp(a, -32.0, 32.0) / a_unit));
    if (tally.tick_search > searches) ++out.steps_over_search_bound;
    out.most_searches_q724 = std::max(out.most_searches_q724, tally.tick_search);
  }
}

template <typename T, typename Law>
void end_stop_runs(const OscillatorParams& p, const EndStopParams& s,
                   const std::vector<double>& floor) {
  EndStopOscillator<T, Counting<Law>> seat;
  CHECK_TRUE(seat.configure(p, s).ok());
  for (double a : floor) seat.step(static_cast<T>(a));
  tally.end_call();
}

}  // namespace

TEST_GROUP(LoopRuns){void setup() override{tally = LoopTally{};
}
}
;

TEST(LoopRuns, TheBlockWalkAndTheTickSearchesOfAStepKeepTheirCountsAndReachThemAtLevelZero) {
  std::mt19937_64 rng(20261130);
  WalkTally walk;
  int levels_seen = 0, most_level = 0;
  for (int n = 0; n < 120; ++n) {
    OscillatorParams p = random_seat(rng, n);
    // Every fourth seat on the firmware's plan: the reference seat at dt = 1 ms (L = 0).
    if (n % 4 == 0) {
      p.mass_kg = 88.4;
      p.stiffness_n_per_m = 11500.0;
      p.dt_s = 1e-3;
    }
    const std::vector<double> floor = hostile_floor(rng, n, 4000);
    int level = 0;
    p.model = FrictionModel::stick_slip;
    walk_runs<double, CoulombStickSlip>(p, floor, walk, level);
    walk_runs<float, CoulombStickSlip>(p, floor, walk, level);
    if (n % 4 == 0) q724_runs<CoulombStickSlip>(p, floor, walk);
    p.model = FrictionModel::stribeck;
    walk_runs<double, StribeckStickSlip>(p, floor, walk, level);
    walk_runs<float, StribeckStickSlip>(p, floor, walk, level);
    levels_seen |= 1 << std::min(level, 30);
    most_level = std::max(most_level, level);
  }
  LONGS_EQUAL(0, walk.steps_over_bound);
  LONGS_EQUAL(1, walk.most_per_step);  // L = 0: one run, reached, in steps of several events too
  // The tick searches: within their bound at every level, which L = 0 reaches (2 with the budget
  // of 3), in float and double and in Q7.24.
  LONGS_EQUAL(0, walk.steps_over_search_bound);
  constexpr long kSearchesAtLevel0 = kMaxEventsOfTheExactSolutionPerStep / 2 + 1;
  LONGS_EQUAL(kSearchesAtLevel0, walk.most_searches_at_level_0);
  LONGS_EQUAL(kSearchesAtLevel0, walk.most_searches_q724);
  CHECK_TRUE(walk.steps_with_several_events > 100);
  CHECK_TRUE((levels_seen & 1) != 0);
  CHECK_TRUE(most_level >= 6);
}

TEST(LoopRuns, TheEndStopScanRunsSixteenBlocksACallItsDipBisectionTwelveAndItSolvesTwoTicks) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 60; ++n) {
    OscillatorParams p = random_seat(rng, n);
    p.dt_s = n % 3 == 0 ? 5e-4 : (n % 3 == 1 ? 1e-3 : 2e-3);
    if (std::sqrt(p.stiffness_n_per_m / p.mass_kg) * p.dt_s > 1.4) p.stiffness_n_per_m = 3e3;
    EndStopParams s;
    s.travel_m = 0.002 + 0.03 * u(rng);
    s.stiffness_n_per_m = 3e4 * std::pow(10.0, 1.5 * u(rng));
    s.damping_ns_per_m = n % 4 < 2 ? 0.0 : 3000.0 * u(rng);
    const std::vector<double> floor = hostile_floor(rng, n, 3000);
    p.model = FrictionModel::stick_slip;
    end_stop_runs<double, CoulombStickSlip>(p, s, floor);
    end_stop_runs<float, CoulombStickSlip>(p, s, floor);
    p.model = FrictionModel::stribeck;
    end_stop_runs<double, StribeckStickSlip>(p, s, floor);
    end_stop_runs<float, StribeckStickSlip>(p, s, floor);
  }
  LONGS_EQUAL(16, tally.most_scan);
  LONGS_EQUAL(kEventLevels - 4, tally.most_dip);
  LONGS_EQUAL(2, tally.most_ticks);
  // The per-call count holds where a dip split the scan in two, and such calls are many.
  CHECK_TRUE(tally.calls_with_a_second_scan > 100);
  CHECK_TRUE(tally.most_scan_with_a_second_scan <= 16);
}

namespace {

// The reference seat stuck at rest, then a floor ramp that takes F_L = -m a_u through -F_fs
// inside one step (a_u from 0.3 to 0.6 m/s^2, F_fs = 45 N at a_u = 0.509): the step's one event
// is a break-away with F_L, and its slip is not searched for a return to rest. `a_unit`: the
// seat's unit of acceleration in m/s^2 (1 in SI units).
template <typename T, typename Seat>
void check_break_away_unsearched(Seat& seat, double a_unit) {
  for (int n = 0; n < 20; ++n) seat.step(T(0.0));
  seat.step(T(0.3 / a_unit));
  tally.tick_search = 0;
  const StepOutput<T> out = seat.step(T(0.6 / a_unit));
  LONGS_EQUAL(1, out.events);
  LONGS_EQUAL(0, tally.tick_search);
  CHECK_TRUE(out.v_r_m_per_s < T(0.0));  // slipping with F_L, away from the floor's push
}

OscillatorParams reference_stick_slip_seat() {
  OscillatorParams p = test::reference_params(FrictionModel::stick_slip, Integrator::exact, 1e-3);
  p.kinetic_friction_n = p.static_friction_n = 45.0;
  return p;
}

template <typename T>
void check_break_away_unsearched_in_si_units() {
  Oscillator<T, Counting<CoulombStickSlip>> seat;
  CHECK_TRUE(seat.configure(reference_stick_slip_seat()).ok());
  check_break_away_unsearched<T>(seat, 1.0);
}

}  // namespace

TEST(LoopRuns, ABreakAwayInsideAStepSlipsToItsEndWithoutASearch) {
  check_break_away_unsearched_in_si_units<double>();
  check_break_away_unsearched_in_si_units<float>();
  OscillatorParams p = reference_stick_slip_seat();
  p.input_range_m_per_s2 = 32.768;
  p.displacement_range_m = 0.1;
  ScaledOscillator<Fixed32, Counting<CoulombStickSlip>> seat;
  CHECK_TRUE(seat.configure(p).ok());
  check_break_away_unsearched<Fixed32>(seat, seat.units().acceleration_m_per_s2());
}
