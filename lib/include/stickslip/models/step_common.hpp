// What every model's step shares (Oscillator, EndStopOscillator): the outputs of a sample, the
// input over a step, the bound on events inside one step and the counters of the guards that keep
// a running model finite and its step time bounded. (Each model keeps its guards inline in its own
// step: a shared helper there moves the compiler's register allocation of the common path.)
#pragma once

#include <cstdint>
#include <type_traits>

namespace stickslip {

template <typename T>
struct StepOutput {
  T x_r_m;              // relative displacement at the end of the step
  T v_r_m_per_s;        // relative velocity
  T a_x_m_per_s2;       // absolute seat acceleration; equals a_u exactly while stuck
  T friction_n;         // friction force F_f on the seat (the holding force while stuck)
  T stuck_time_s;       // time spent stuck inside this step
  T stuck_fraction;     // the same as a fraction of the step, in [0, 1] (exact sums in float too)
  bool stuck;           // stuck at the end of the step
  std::uint8_t events;  // stick, break-away and reversal events inside this step
};

// A safety limit on events inside one step, for the models whose events are not bounded below
// it by the argument that follows: the end-stop model (its contacts and releases come on top of
// the friction's events) and Stribeck (its slip force changes with v_r inside a piece of motion).
// At it the step finishes in its current mode, which keeps the worst-case time of step()
// bounded; a step where that lost an event is counted in SafetyCounters::event_budget_exhausted
// (the end-stop model counts every step that reaches it).
inline constexpr int kMaxEventsPerStep = 32;

// The most events the exact solution of a law with a stuck state and a constant slip force
// (Coulomb stick-slip, F_fs >= F_fk; the held signum law, F_fs = F_fk, which holds the load to
// the step's end once at rest; the smoothed laws stop at their first event) has in one step, for
// every step configure() accepts (omega0 dt <= pi/2), with a_u linear and the actuator force held
// over the step: Oscillator's event budget for these laws, every scalar. F_L = f_a - m a_u - k x_r,
// the force that holds the seat at rest, moves one way, s, all step (at any fixed x_r; linear in
// time), and:
//   - a slip that starts from rest inside the step in the direction d = s does not return to rest
//     in it. Counted from its start, y = (x_r - x_r(0)) d obeys m y'' + b y' + k y = f(t),
//     y(0) = y'(0) = 0, with f = F_L d - F_fk: f(0) >= F_fs - F_fk >= 0 by the stick decision and
//     f' >= 0. So y'(t) = g(t) f(0) + (the integral from 0 to t of g(t - tau) f'(tau) dtau), where
//     g is the displacement's impulse response, e^(-zeta omega0 t) sin(omega_d t) / (m omega_d):
//     positive until omega_d t = pi, which is beyond the step since omega_d <= omega0 and
//     omega0 dt <= pi/2 (and for zeta >= 1 positive for all t). So y' > 0 all step;
//   - a break-away inside the step goes the way F_L moves, s (one at the step's start, where f_a
//     may jump, may go against it);
//   - where a slip returns to rest, F_L d <= F_fk at the x_r reached (m y'' <= 0 there): it sticks
//     or reverses, never slips on the same way, and a reversal of a slip against s goes towards s;
//     a stick ends in a break-away towards s, or lasts to the step's end.
// So only a slip entering the step, or one against s, returns to rest, and the longest chains are
// (a break-away against s at the start, or a slip entering towards s that comes to rest and
// reverses), a return to rest that sticks, a break-away towards s: 3 events.
// tests/core/test_stick_slip.cpp counts them on a run 32 times finer, up to omega0 dt = pi/2.
inline constexpr int kMaxEventsOfTheExactSolutionPerStep = 3;

namespace law_detail {
// A law's declared event budget (`static constexpr int kEventBudget`, 1 to kMaxEventsPerStep), or
// 0 where it declares none: for an integrator whose frame cannot afford the model's own budget
// (its steps then lose events, and count them), and for the tests that reach a model's budget.
template <typename Law, typename = void>
inline constexpr int kDeclaredEventBudget = 0;
template <typename Law>
inline constexpr int kDeclaredEventBudget<Law, std::void_t<decltype(Law::kEventBudget)>> =
    Law::kEventBudget;
// The law's declared budget if it declares one, else `bound`.
template <typename Law>
constexpr int event_budget(int bound) noexcept {
  return kDeclaredEventBudget<Law> > 0 ? kDeclaredEventBudget<Law> : bound;
}
}  // namespace law_detail

// The loops and calls of a step whose counts the static bound takes per step or per call rather
// than per entry or per call site (port/baremetal/loop-bounds.json): a law that declares
// `static void count_loop_run(LoopRun) noexcept` is told of every run of their bodies, of each
// search of a tick's polynomial for v_r = 0, and of each call of the end-stop search's move to a
// mode's end and each tick that move solves itself, so that a test can count them
// (tests/core/test_loop_runs.cpp). For every other law the call compiles to nothing.
enum class LoopRun : std::uint8_t {
  block_walk,     // Oscillator: one run of slip()'s block walk
  tick_search,    // Oscillator: one search of a tick's polynomial for v_r = 0 (first_crossing())
  mode_search,    // EndStopOscillator: a call of move_to_mode_end() begins
  mode_tick,      // EndStopOscillator: move_to_mode_end() solves a tick (its start's or a dip's)
  scan_block,     // EndStopOscillator: one run of the scan, one block
  dip_bisection,  // EndStopOscillator: one halving of the block where |v_r| dips
};

namespace law_detail {
template <typename Law, typename = void>
inline constexpr bool kCountsLoopRuns = false;
template <typename Law>
inline constexpr bool kCountsLoopRuns<Law, std::void_t<decltype(&Law::count_loop_run)>> = true;

template <typename Law>
inline void count_loop_run(LoopRun run) noexcept {
  if constexpr (kCountsLoopRuns<Law>) {
    Law::count_loop_run(run);
  } else {
    (void)run;
  }
}
}  // namespace law_detail

// Every count stays 0 for an accepted configuration driven by finite input; a non-zero count says
// which guard kept the run finite and bounded.
struct SafetyCounters {
  std::uint64_t event_budget_exhausted = 0;  // steps the event budget cut short
  std::uint64_t rejected_inputs = 0;         // non-finite inputs replaced by the previous sample
  std::uint64_t state_resets = 0;            // non-finite states restarted from rest
  std::uint64_t saturated_steps = 0;         // fixed point: steps in which an operation saturated
};

// The outputs of a step run on the shifted input a_u - f_a/m (an actuator force f_a held over the
// step), made those of a_u with f_a: stuck, the seat moves with the floor (a_x = a_u exactly);
// slipping, a_x gains f_a/m. (The friction output is already F_L = f_a - (m a_u + k x_r).)
template <typename T>
inline void actuated_step_output(StepOutput<T>& out, T a_u, T accel_offset) noexcept {
  out.a_x_m_per_s2 = out.stuck ? a_u : out.a_x_m_per_s2 + accel_offset;
}

// The input over the current step, linear in the fraction of the step phi in [0, 1]
// (first-order hold between the samples a0 and a1).
template <typename T>
struct StepInput {
  T a0, a1;
  T at(T phi) const noexcept { return (T(1) - phi) * a0 + phi * a1; }  // exact at both ends
};

}  // namespace stickslip
