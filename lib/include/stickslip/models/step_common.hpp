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

// Safety limit on events inside one step; beyond it the step finishes in its current mode. Keeps
// the worst-case time of step() bounded; counted in SafetyCounters::event_budget_exhausted.
inline constexpr int kMaxEventsPerStep = 32;

// Every count stays 0 for an accepted configuration driven by finite input; a non-zero count says
// which guard kept the run finite and bounded.
struct SafetyCounters {
  std::uint64_t event_budget_exhausted = 0;  // steps that hit kMaxEventsPerStep
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
