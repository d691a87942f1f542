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

// A safety limit on events inside one step, for the configurations whose events are not bounded
// below it by the arguments that follow: Stribeck where its slip force changes with v_r inside a
// piece of motion (under RK4, which evaluates it at its stages; with end stops, where the held
// force is taken again at contacts and releases). At it the step finishes in its current mode,
// which keeps the worst-case time of step() bounded; a step where that lost an event is counted in
// SafetyCounters::event_budget_exhausted (the end-stop model counts every step that reaches it).
inline constexpr int kMaxEventsPerStep = 32;

// The most events the exact solution of a law with a stuck state and a slip force constant over
// each piece of motion (Coulomb stick-slip, F_fs >= F_fk; Stribeck with its force held at its
// value where the piece starts, below; the held signum law, F_fs = F_fk, which holds the load to
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
// The argument asks two things of a piece's slip force F_p: F_p <= abs(F_L) where a piece starts
// from rest (f(0) >= 0), and F_p <= F_fs where a piece returns to rest (it sticks or reverses).
// Stribeck's held force, F_fk + (F_fs - F_fk) exp(-(v_r/v_S)^2) at the piece's start, meets
// both: from rest it is F_fs, which a break-away or a reversal exceeds, and it never exceeds F_fs
// (F_fs >= F_fk, configure() checks). So its budget is 3 as well, wherever the force is held.
// tests/core/test_stick_slip.cpp counts them on a run 32 times finer, up to omega0 dt = pi/2, and
// Stribeck's with a budget of kMaxEventsPerStep.
inline constexpr int kMaxEventsOfTheExactSolutionPerStep = 3;

// The same bound with end stops (EndStopOscillator: Kelvin-Voigt stops of stiffness k_s and
// damping b_s beyond +-travel, configure() accepting omega_c dt <= pi/2, omega_c^2 = (k + k_s)/m),
// for Coulomb stick-slip and for no friction. The friction's argument above holds with the stops:
// with y, d and f = F_L d - F_fk as there (F_L now holding the stop's force too, which at fixed
// x_r is constant), a slip from rest towards s obeys m y'' = g(t) - R(y) - c y', where
// g(0) >= 0, g' >= 0, R(0) = 0 and R (the springs' force) rises with a slope between k and
// k + k_s, and c (b, or b + b_s in a stop) >= 0. With P = sqrt(m (k + k_s)) y', z = g - R(y) and
// theta the angle of (z, P): while y' >= 0, z' >= -omega_c P, so in the first quadrant
// theta' <= omega_c - c z P / (m (z^2 + P^2)) <= omega_c, and theta, starting at 0, stays in
// (0, pi/2] for the step (omega_c dt <= pi/2), while z^2 + P^2 cannot reach 0 (it falls at most
// as fast as e^(-2 c t / m)): y' > 0 all step, through any contact or release. The other steps
// of the argument use F_L at rest and at fixed x_r alone, so they hold too: at most 3 friction
// events, and at most 3 pieces of motion (a slip entering the step towards s that reverses, a
// slip against s that comes to rest, a slip towards s). x_r is monotonic in each piece, so each
// crosses each of the two edges, +travel and -travel, at most once: a contact or a release,
// 2 per piece. Without friction v_r = 0 is no event, and the same argument (F_fk = 0) leaves at
// most 3 monotonic pieces. Stribeck's held slip force changes at contacts and releases, so g may
// fall inside a piece: it keeps kMaxEventsPerStep. tests/core/test_end_stops.cpp counts the
// events on a run 32 times finer, on hostile floors, seats at the ends of what configure()
// accepts and strokes of nanometres on white noise (most: 8 with Coulomb; without friction 6,
// the bound, in sweeps of such sets).
inline constexpr int kMaxStrokeEdgeEventsOfTheExactSolutionPerStep = 6;
inline constexpr int kMaxEndStopEventsOfTheExactSolutionPerStep = 9;
static_assert(kMaxStrokeEdgeEventsOfTheExactSolutionPerStep == 3 * 2 &&
                  kMaxEndStopEventsOfTheExactSolutionPerStep ==
                      kMaxEventsOfTheExactSolutionPerStep +
                          kMaxStrokeEdgeEventsOfTheExactSolutionPerStep,
              "3 pieces of motion, each crossing each of the 2 edges at most once");

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
