// Den Hartog's friction factor K = 4 F_fk / (pi sqrt(2) m a0u), a0u = RMS of a_u, and the friction
// regime it implies: below ~0.4 the signum model suffices, above ~0.75 the mass sticks more than
// half the time and only the stick-slip model is right.
#pragma once

namespace stickslip {

inline constexpr double kSignumSufficesBelowK = 0.4;
inline constexpr double kStickSlipRequiredAboveK = 0.75;

enum class FrictionRegime : unsigned char { signum_suffices, transition, stick_slip_required };

// K; +infinity for a0u = 0 with friction, 0 without friction.
double den_hartog_factor(double kinetic_friction_n, double mass_kg, double rms_u_m_per_s2) noexcept;

FrictionRegime friction_regime(double den_hartog_k) noexcept;
const char* regime_name(FrictionRegime regime) noexcept;

}  // namespace stickslip
