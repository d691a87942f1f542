// Den Hartog's harmonic balance for the seat with Coulomb friction under harmonic base
// acceleration a_u = A sin(w t): the friction force is replaced by its fundamental, a viscous force
// with c_eq = 4 F_fk / (pi w X), which gives the steady-state relative amplitude X from
//   [(k - m w^2)^2 + (b w)^2] X^2 + 2 b w f X + f^2 - (m A)^2 = 0,   f = 4 F_fk / pi
// (Den Hartog 1931; the paper's eqs. (11)-(12)). In Den Hartog's factor for a harmonic input,
// K = 4 F_fk / (pi sqrt2 m a0u) = f / (m A) with a0u = A/sqrt2, a positive root exists only for
// K < 1: at K >= 1 the friction's fundamental alone can hold the whole inertial force, the mass
// sticks for part of every cycle, and the method no longer applies (valid = false).
#pragma once

namespace stickslip::host {

struct HarmonicBalance {
  bool valid = false;                   // K < 1: a continuous-slip solution exists
  double den_hartog_k = 0.0;            // f / (m A)
  double relative_amplitude_m = 0.0;    // X, amplitude of x_r
  double phase_rad = 0.0;               // lag of x_r behind the inertial force -m a_u
  double equivalent_damping_ns_per_m = 0.0;  // b + 4 F_fk / (pi w X)
  double seat_acceleration_amplitude_m_per_s2 = 0.0;  // |a_x| of the fundamental
  double transmissibility = 0.0;        // seat over floor amplitude (fundamental only)
};

HarmonicBalance harmonic_balance(double mass_kg, double stiffness_n_per_m, double damping_ns_per_m,
                                 double kinetic_friction_n, double amplitude_m_per_s2,
                                 double frequency_hz) noexcept;

}  // namespace stickslip::host
