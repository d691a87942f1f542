// The end-stop seat at its event budget: the path no step of the default laws reaches (hostile
// floors put at most 4 events in one step, 5 on seats at the ends of what configure() accepts,
// against a budget of 10 for Coulomb, one above the exact solution's bound, and the safety limit
// kMaxEventsPerStep = 32 for Stribeck: test_end_stops.cpp), reached here by laws that declare a
// budget of 1 or 2. From the same state as a seat with the full budget (both reset to it every
// step), on floors that drive random seats into their stops: a step with fewer events than the
// budget is the full seat's, bit for bit; a step with more locates the budget's events and finishes
// in its mode (stuck with v_r = 0, or slipping with the friction of its direction, in its contact
// mode), and is counted, as is every step that reaches the budget before its end. Among them are
// steps that lost an event: stuck with |F_L| beyond F_fs, slipping with v_r against its direction,
// or beyond a stop's edge in the free mode or inside the stroke in contact. The event loop's trip
// count, kEventBudget + 1 passes, is reached and never exceeded.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stop_seats.hpp"

using namespace stickslip;

namespace {

// The law with a declared budget, counting the passes of the event loop that move the seat
// (move_to_mode_end(); a stuck pass calls break_away() instead and locates at most one event).
template <typename Law, int kBudget>
struct WithBudget : Law {
  static constexpr int kEventBudget = kBudget;
  static inline int mode_searches = 0;
  static void count_loop_run(LoopRun run) noexcept {
    if (run == LoopRun::mode_search) ++mode_searches;
  }
};

struct BudgetTally {
  long steps_below_budget = 0;
  long steps_over_budget = 0;  // the full seat had more events than the budget
  long counted = 0;
  long counted_stuck = 0;     // counted, ending stuck
  long counted_slipping = 0;  // counted, ending slipping
  long lost = 0;              // ending with an event lost (all of them counted)
  long lost_stroke = 0;       // of those, a contact or release lost
  int most_mode_searches = 0;
};

// How far rounding may carry the seat's own judgement of a quantity built from terms of size
// `terms` (in T): verdicts within it go either way.
template <typename T>
double rounding_of(double terms) {
  return 64.0 * static_cast<double>(std::numeric_limits<T>::epsilon()) * terms;
}

template <typename T, typename Law, int kBudget>
void check_budget(const test::RandomStopSeat& r, std::uint64_t seed, long steps,
                  BudgetTally& tally) {
  using Cut = WithBudget<Law, kBudget>;
  EndStopOscillator<T, Law> full;
  EndStopOscillator<T, Cut> cut;
  static_assert(decltype(cut)::kEventBudget == kBudget);
  static_assert(decltype(full)::kEventBudget ==
                (Law::velocity_dependent ? kMaxEventsPerStep
                                         : kMaxEndStopEventsOfTheExactSolutionPerStep + 1));
  CHECK_TRUE(full.configure(r.seat, r.stops).ok());
  CHECK_TRUE(cut.configure(r.seat, r.stops).ok());
  const double m = r.seat.mass_kg, k = r.seat.stiffness_n_per_m, travel = r.stops.travel_m;
  const double k_s = r.stops.stiffness_n_per_m;
  const double f_fk = r.seat.kinetic_friction_n, f_fs = r.seat.static_friction_n;
  const bool constant_slip_force = !Law::velocity_dependent;
  test::SplitMix64 random(seed);
  T a_previous = T(0);
  for (long n = 0; n < steps; ++n) {
    const T x = full.x_r(), v = full.v_r();
    const double a_u =
        test::hostile_stop_floor(r, n, static_cast<double>(x), static_cast<double>(v),
                                 static_cast<double>(full.stop_force_n()), random);
    full.reset(x, v, a_previous);
    cut.reset(x, v, a_previous);
    a_previous = static_cast<T>(a_u);
    Cut::mode_searches = 0;
    const StepOutput<T> expected = full.step(a_previous);
    const StepOutput<T> got = cut.step(a_previous);
    const bool counted = cut.event_budget_exhausted() != 0;  // reset() cleared it
    CHECK_EQUAL(0u, full.event_budget_exhausted());
    CHECK_TRUE(Cut::mode_searches <= kBudget + 1);
    tally.most_mode_searches = std::max(tally.most_mode_searches, Cut::mode_searches);
    const auto text = [&](const char* what) {
      return StringFromFormat("%s: step %ld, events %d (budget %d) -> %d, x_r %.17g vs %.17g", what,
                              n, expected.events, kBudget, got.events,
                              static_cast<double>(got.x_r_m), static_cast<double>(expected.x_r_m));
    };
    if (expected.events < kBudget) {
      ++tally.steps_below_budget;
      CHECK_TEXT(test::same_bits(expected, got) && cut.contact() == full.contact(),
                 text("below the budget").asCharString());
      CHECK_TEXT(!counted, text("counted below the budget").asCharString());
      continue;
    }
    // The budget's events are the full seat's; after the last of them no search runs.
    CHECK_TEXT(got.events == kBudget, text("events at or over the budget").asCharString());
    if (expected.events > kBudget) {
      ++tally.steps_over_budget;
      CHECK_TEXT(counted, text("over the budget, not counted").asCharString());
    } else if (constant_slip_force) {
      // The full seat found nothing after its last event: the same mode to the step's end.
      CHECK_TEXT(got.stuck == expected.stuck && cut.contact() == full.contact(),
                 text("at the budget").asCharString());
    }
    if (!counted) continue;  // its last event at the step's end
    ++tally.counted;
    const double x_r = static_cast<double>(got.x_r_m), v_r = static_cast<double>(got.v_r_m_per_s);
    const int contact = cut.contact();
    const double edge = travel * contact;
    bool lost = false, lost_stroke = false;
    // The mode's stroke: beyond the edge of a stop in the free mode, or inside the stroke in
    // contact, is a contact or release lost.
    const double stroke_rounding = rounding_of<T>(travel + std::fabs(x_r));
    if (contact == 0) {
      lost_stroke = std::fabs(x_r) > travel + stroke_rounding;
    } else {
      lost_stroke = (x_r - edge) * contact < -stroke_rounding;
    }
    if (got.stuck) {
      ++tally.counted_stuck;
      // Finished stuck: at rest, holding the load to the step's end.
      CHECK_TEXT(v_r == 0.0 && got.stuck_fraction > T(0), text("stuck end").asCharString());
      const double spring = k * x_r + (contact == 0 ? 0.0 : k_s * (x_r - edge));
      const double limit = -m * a_u - spring;
      const double margin =
          rounding_of<T>(m * std::fabs(a_u) + k * std::fabs(x_r) +
                         (contact == 0 ? 0.0 : k_s * (std::fabs(x_r) + travel)) + f_fs);
      lost = std::fabs(limit) > f_fs + margin;
    } else {
      ++tally.counted_slipping;
      // Finished slipping: the friction of the slip's direction (Coulomb's F_fk) to the end.
      const double friction = static_cast<double>(got.friction_n);
      const double direction = friction > 0.0 ? 1.0 : -1.0;
      CHECK_TEXT(friction != 0.0, text("slipping end").asCharString());
      if (constant_slip_force)
        CHECK_TEXT(friction == static_cast<double>(static_cast<T>(f_fk)) * direction,
                   text("slip friction").asCharString());
      lost = v_r * direction < 0.0;
    }
    if (lost || lost_stroke) {
      ++tally.lost;
      if (lost_stroke) ++tally.lost_stroke;
    }
  }
  CHECK_EQUAL(0u, full.state_resets());
  CHECK_EQUAL(0u, cut.state_resets());
}

template <typename Law, int kBudget>
void run_law(FrictionModel model, std::uint64_t seed, BudgetTally& in_double,
             BudgetTally& in_float) {
  test::SplitMix64 random(seed);
  for (int i = 0; i < 24; ++i) {
    const test::RandomStopSeat r = test::random_stop_seat(random, model);
    const std::uint64_t floor_seed = random.next();
    check_budget<double, Law, kBudget>(r, floor_seed, 4000, in_double);
    if (test::float_resolves_the_friction_at_the_stop(r))
      check_budget<float, Law, kBudget>(r, floor_seed, 4000, in_float);
  }
}

// Every branch of the budget's handling is reached: steps below it and over it, counted steps
// ending stuck and slipping, lost events (a contact or release among them), and the event loop's
// last pass.
void check_reached(const BudgetTally& t, int budget, const char* what) {
  CHECK_TEXT(t.steps_below_budget > 10000, what);
  CHECK_TEXT(t.steps_over_budget > 100,
             StringFromFormat("%s: %ld over", what, t.steps_over_budget).asCharString());
  CHECK_TEXT(t.counted_stuck > 0 && t.counted_slipping > 0, what);
  CHECK_TEXT(t.lost > 0 && t.lost_stroke > 0, what);
  LONGS_EQUAL_TEXT(budget + 1, t.most_mode_searches, what);
  test::note_margin(what, static_cast<double>(t.lost), static_cast<double>(t.counted));
}

template <typename Law>
void check_law(FrictionModel model, std::uint64_t seed, const char* what) {
  BudgetTally double_1, float_1, double_2, float_2;
  run_law<Law, 1>(model, seed, double_1, float_1);
  run_law<Law, 2>(model, seed, double_2, float_2);
  check_reached(double_1, 1, what);
  check_reached(float_1, 1, what);
  check_reached(double_2, 2, what);
  check_reached(float_2, 2, what);
}

}  // namespace

TEST_GROUP(EndStopEventBudget){};

TEST(EndStopEventBudget, StickSlipAtItsBudgetFinishesInItsModeAndCountsEveryStepCutShort) {
  check_law<CoulombStickSlip>(
      FrictionModel::stick_slip, 21,
      "end stops, stick-slip (double, float; budget 1, 2): lost of counted");
}

TEST(EndStopEventBudget, StribeckAtItsBudgetFinishesInItsModeAndCountsEveryStepCutShort) {
  check_law<StribeckStickSlip>(FrictionModel::stribeck, 22,
                               "end stops, Stribeck (double, float; budget 1, 2): lost of counted");
}
