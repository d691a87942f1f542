#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip {

double den_hartog_factor(double kinetic_friction_n, double mass_kg,
                         double rms_u_m_per_s2) noexcept {
  return den_hartog_factor_in(kinetic_friction_n, mass_kg, rms_u_m_per_s2);
}

const char* regime_name(FrictionRegime regime) noexcept {
  switch (regime) {
    case FrictionRegime::signum_suffices:
      return "signum suffices";
    case FrictionRegime::transition:
      return "transition";
    case FrictionRegime::stick_slip_required:
      return "stick-slip required";
  }
  return "?";
}

}  // namespace stickslip
