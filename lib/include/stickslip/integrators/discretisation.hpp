// configure(): validation and every precomputed coefficient, in double, once per scene.
// All divisions, square roots and matrix exponentials of the library happen here.
#pragma once

#include "stickslip/core/params.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/integrators/step_map.hpp"

namespace stickslip {

// Everything the step needs, in double; Oscillator<T>::configure converts it to T.
struct DiscreteModel {
  OscillatorParams params;
  StepMap<double> maps[kMapLevels];  // maps[l] advances dt / 2^l with the chosen integrator
  double block_s[kMapLevels];        // dt / 2^l
  double inv_dt;                     // 1/dt, for the input slope inside a step
  double inv_mass;                   // 1/m
  double stiffness_over_mass;        // k/m
  double damping_over_mass;          // b/m
  double stribeck_excess_n;          // F_fs - F_fk
  double inv_stribeck_velocity;      // 1/v_S
  double smoothing_scale_n;          // F_fk, or F_fk*2/pi for the atan form
  double natural_frequency_rad_s;    // sqrt(k/m)
  double spectral_radius;            // of the one-step map linearised at v_r = 0
};

// How the in-step event search resolves an event. It bisects on the dyadic grid of the step down
// to blocks of dt / 2^tick_level ("ticks"); inside a tick it either evaluates the exact solution
// as a Taylor polynomial of degree taylor_order in v_r (exact integrator: the tick is chosen so
// that rate * tick <= 1/16 and the order so that the truncation is below epsilon/16, with
// rate = omega0 + b/m bounding the system's matrix), or interpolates linearly inside ticks of
// dt / 2^kEventLevels (taylor_order = 0: the other integrators, whose trajectory between
// sub-steps is their own, and scenes too stiff for a Taylor tick of at least dt / 2^kEventLevels).
struct EventSearchPlan {
  int tick_level;
  int taylor_order;
};
EventSearchPlan event_search_plan(const OscillatorParams& params, double epsilon) noexcept;

// Validates `params` (finite, physical ranges, F_fs >= F_fk, the integrator's stability limit,
// the event search's step limit) and fills `out`. The message names the parameter and the limit.
ConfigResult discretise(const OscillatorParams& params, DiscreteModel& out) noexcept;

// Affine one-step map of `integrator` for the linear system x' = v, v' = -k/m x - c/m v + g(t)
// over `step_s` with first-order-hold g. Exposed for tests and tools.
StepMap<double> linear_step_map(Integrator integrator, double stiffness_over_mass,
                                double damping_over_mass, double step_s) noexcept;

// The map over dt / 2^level of `params`' integrator (params as discretise() validates them),
// with the identity split off its diagonal where xx > 1/2 (NearIdentityStepMap, step_map.hpp):
// double's form of every map. For the exact integrator every coefficient is the exact one to a
// double's precision, xx - 1 and vv - 1 included; the other integrators' diagonals are their
// map's less 1, since their own truncation is far above the double's rounding of xx.
NearIdentityStepMap<double> near_identity_step_map(const OscillatorParams& params,
                                                   int level) noexcept;

// A model's map over dt / 2^level in the form its scalar keeps (StepMapOf): double's from
// near_identity_step_map(params, ...), the others' from model.maps (model discretised from params).
template <typename T>
StepMapOf<T> step_map_of(const DiscreteModel& model, const OscillatorParams& params,
                         int level) noexcept {
  if constexpr (std::is_same_v<StepMapOf<T>, StepMap<T>>) {
    (void)params;
    return StepMap<T>::from_double(model.maps[level]);
  } else {
    (void)model;
    return StepMapOf<T>::from_double(near_identity_step_map(params, level));
  }
}

// Largest eigenvalue modulus of the 2x2 block [[xx, xv], [vx, vv]].
double spectral_radius(const StepMap<double>& map) noexcept;

}  // namespace stickslip
