// What every model's step shares (Oscillator, EndStopOscillator): the outputs of a sample, the
// input over a step, the bound on events inside one step and the counters of the guards that keep
// a running model finite and its step time bounded. (Each model keeps its guards inline in its own
// step: a shared helper there moves the compiler's register allocation of the common path.)
#pragma once

#include <cstdint>

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

// Safety limit on events inside one step; at it the step finishes in its current mode. Keeps the
// worst-case time of step() bounded; a step where that lost an event (stuck to the end with |F_L|
// beyond F_fs, or slipping to the end with v_r against its direction) is counted in
// SafetyCounters::event_budget_exhausted (the end-stop model counts every step that reaches it).
inline constexpr int kMaxEventsPerStep = 32;

// The most events the exact solution of a law with a stuck state has in one step when
//   (b/m) dt + (k/m) dt^2 / 2 < 1
// (the reference seat: dt below 88 ms), with a_u linear and the actuator force held over the step
// (Stribeck: read its slip friction, at most F_fs and falling with speed, for F_fk below).
// F_L = f_a - m a_u - k x_r, the force that holds the seat at rest, then moves one way, s, all
// step (at any fixed x_r), and:
//   - a slip that starts from rest inside the step in the direction s does not return to rest in
//     it. With w = v_r d and z = x_r d counted from its start, Delta = F_L d - F_fk >= 0 there and
//     F_L d growing at c >= 0: w <= (Delta t + c t^2/2)/m and z <= (Delta t^2/2 + c t^3/6)/m, so
//     m w' >= Delta (1 - b t/m - k t^2/(2m)) + c t (1 - b t/(2m) - k t^2/(6m)) > 0;
//   - a break-away inside the step goes the way F_L moves, s (one at the step's start, where f_a
//     may jump, may go against it);
//   - where a slip returns to rest, F_L d <= F_fk at the x_r reached (m w' <= 0 there): it sticks
//     or reverses, never slips on the same way, and a reversal of a slip against s goes towards s;
//     a stick ends in a break-away towards s, or lasts to the step's end.
// So only a slip entering the step, or one against s, returns to rest, and the longest chains are
// (a break-away against s at the start, or a slip entering towards s that comes to rest and
// reverses), a return to rest that sticks, a break-away towards s: 3 events. Q7.24 takes this as
// its budget, and its configure() refuses steps beyond the condition: the bound on its step's
// work is then the exact solution's own. The other scalars accept coarser steps, where the exact
// solution may need more, and keep kMaxEventsPerStep.
inline constexpr int kMaxEventsOfTheExactSolutionPerStep = 3;

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
