#include "stickslip/host/harmonic_balance.hpp"

#include <cmath>

namespace stickslip::host {

HarmonicBalance harmonic_balance(double mass_kg, double stiffness_n_per_m, double damping_ns_per_m,
                                 double kinetic_friction_n, double amplitude_m_per_s2,
                                 double frequency_hz) noexcept {
  constexpr double kPi = 3.14159265358979323846;
  HarmonicBalance out;
  const double w = 2.0 * kPi * frequency_hz;
  const double force = mass_kg * amplitude_m_per_s2;  // inertial force amplitude, N
  const double f = 4.0 * kinetic_friction_n / kPi;    // friction's fundamental, N
  out.den_hartog_k = force > 0.0 ? f / force : (f > 0.0 ? HUGE_VAL : 0.0);
  const double detuning = stiffness_n_per_m - mass_kg * w * w;
  const double viscous = damping_ns_per_m * w;
  const double d = detuning * detuning + viscous * viscous;
  if (!(out.den_hartog_k < 1.0) || !(d > 0.0)) return out;
  // The positive root of d X^2 + 2 viscous f X + f^2 - force^2 = 0.
  const double x = (-viscous * f + std::sqrt(viscous * viscous * f * f - d * (f * f - force * force))) / d;
  if (!(x > 0.0)) return out;
  out.valid = true;
  out.relative_amplitude_m = x;
  const double dissipative = viscous + f / x;  // (b + c_eq) w
  out.equivalent_damping_ns_per_m = dissipative / w;
  out.phase_rad = std::atan2(dissipative, detuning);
  // a_x = -(k x_r + (b + c_eq) v_r)/m for the fundamental.
  out.seat_acceleration_amplitude_m_per_s2 = std::hypot(stiffness_n_per_m, dissipative) * x / mass_kg;
  out.transmissibility = out.seat_acceleration_amplitude_m_per_s2 / amplitude_m_per_s2;
  return out;
}

}  // namespace stickslip::host
