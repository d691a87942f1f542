// The tuning and the seat of the state estimator (observer/state_estimator.hpp), in SI units.
#pragma once

namespace stickslip {

struct StateEstimatorParams {
  // The seat: known (k, b, m) and the friction levels the estimates start from.
  double mass_kg = 88.4;
  double stiffness_n_per_m = 11500.0;
  double damping_ns_per_m = 504.0;
  double initial_kinetic_friction_n = 45.0;  // F_fk estimate at reset
  double initial_static_friction_n = 45.0;   // F_fs estimate at reset (>= F_fk)
  double dt_s = 1e-3;
  // Sensors (per-sample RMS noise, white).
  double seat_acceleration_noise_m_per_s2 = 0.02;   // a_x
  double floor_acceleration_noise_m_per_s2 = 0.02;  // a_u
  double travel_noise_m = 3e-5;                     // x_r, before quantisation
  double travel_resolution_m = 1e-4;                // x_r quantum (adds resolution^2/12)
  // Process noise while slipping: the friction force's random walk (drift, unmodelled friction
  // dynamics) and a force on the seat the model does not know (as a white force, RMS per sample).
  double friction_walk_n_per_sqrt_s = 20.0;
  double model_force_noise_n = 1.0;
  // F_f uncertainty at a break-away (the jump from the holding force to F_fk is not known yet).
  double breakaway_friction_uncertainty_n = 10.0;
  // Learning.
  double kinetic_friction_time_s = 0.5;  // averaging time of F_fk samples (slip time)
  double static_friction_weight = 0.1;   // weight of one break-away's F_fs sample
  double bias_time_s = 2.0;              // averaging time of the a_x - a_u bias (stuck time)
  // Stuck decision (measurement based).
  double stick_velocity_m_per_s = 1e-3;       // |v_r| below: may be stuck
  double stick_acceleration_m_per_s2 = 0.08;  // low-passed |a_x - a_u - bias| below: may be stuck
  double acceleration_filter_time_s = 0.004;  // that low-pass
  double breakaway_velocity_m_per_s = 3e-4;   // integrated a_x - a_u - bias to break away
  double breakaway_leak_time_s = 0.01;        // leak of that integral (bounds its noise)
  double slip_confidence_m_per_s = 2e-3;      // |v_r| above: the slip direction is certain
  double event_velocity_m_per_s = 5e-3;       // |v_r| below: a missed stick or reversal possible
  double event_gate_sigma = 5.0;              // a_x innovation beyond this many sigma: an event
};

}  // namespace stickslip
