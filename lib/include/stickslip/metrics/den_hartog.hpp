// Den Hartog's friction factor K = 4 F_fk / (pi sqrt(2) m a0u), a0u = RMS of a_u, and the friction
// regime it implies: below ~0.4 the signum model suffices, above ~0.75 the mass sticks more than
// half the time and only the stick-slip model is right.
#pragma once

#include <cmath>
#include <limits>

namespace stickslip {

inline constexpr double kSignumSufficesBelowK = 0.4;
inline constexpr double kStickSlipRequiredAboveK = 0.75;

enum class FrictionRegime : unsigned char { signum_suffices, transition, stick_slip_required };

// K in R (float or double); +infinity for a0u = 0 with friction, 0 without friction.
template <typename R>
R den_hartog_factor_in(R kinetic_friction_n, R mass_kg, R rms_u_m_per_s2) noexcept {
  if (kinetic_friction_n == R(0)) return R(0);
  if (!(rms_u_m_per_s2 > R(0)) || !(mass_kg > R(0))) return std::numeric_limits<R>::infinity();
  const R pi = R(3.14159265358979323846);
  return R(4) * kinetic_friction_n / (pi * std::sqrt(R(2)) * mass_kg * rms_u_m_per_s2);
}

// K in double.
double den_hartog_factor(double kinetic_friction_n, double mass_kg, double rms_u_m_per_s2) noexcept;

// The regime K says, in K's own type R (float or double): the boundaries are R's nearest.
template <typename R>
FrictionRegime friction_regime(R den_hartog_k) noexcept {
  if (den_hartog_k < R(kSignumSufficesBelowK)) return FrictionRegime::signum_suffices;
  if (den_hartog_k > R(kStickSlipRequiredAboveK)) return FrictionRegime::stick_slip_required;
  return FrictionRegime::transition;
}
const char* regime_name(FrictionRegime regime) noexcept;

}  // namespace stickslip
