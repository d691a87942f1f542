// configure()'s check of a scene against a fixed-point format (core/fixed_point.hpp): every
// coefficient, and every intermediate the step forms at the declared input and displacement
// ranges, must fit, and the small coefficients must keep their precision.
#pragma once

#include "stickslip/core/params.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/integrators/discretisation.hpp"

namespace stickslip {

// Largest magnitude the check allows for a coefficient or an intermediate: a quarter of the
// format's range, so that the step's sums of up to four such terms cannot overflow.
inline constexpr int kFixedPointHeadroomBits = 2;
// Smallest non-zero coefficient, in units of the resolution: rounding a coefficient to the format
// then changes it by at most 2^-11 of its value.
inline constexpr double kFixedPointMinimumSteps = 1024.0;

// The units `params` are in: SI, or the scene units of a ScaledOscillator (time dt, mass m, length
// L; models/scaled_oscillator.hpp), in which a refusal then states its values.
enum class ParameterUnits { si, scene };

// The units a model on scalar traits S takes its parameters in (ScalarTraits::kSceneUnits).
template <typename S>
constexpr ParameterUnits parameter_units() noexcept {
  return S::kSceneUnits ? ParameterUnits::scene : ParameterUnits::si;
}

// Checks `params` (already validated by discretise(), which filled `model`) for a Q(I).(F) scalar,
// I = integer_bits, F = fraction_bits: the laws and integrators fixed point offers (linear,
// signum, smooth with the rational form, stick-slip; euler, symplectic, exact), the ranges
// params.input_range_m_per_s2 and params.displacement_range_m, every coefficient's magnitude and
// precision, and the step's intermediates at those ranges (input force m a_u, spring force k x_r,
// damper force b v_r with v_r up to omega0 X + A/omega0, limit force, seat acceleration, c v_r).
// The message starts with the parameter to change and names the quantity that would not fit.
// tick_level: the event search's ticks are dt / 2^tick_level (they must keep their precision too).
ConfigResult check_fixed_point_scene(const OscillatorParams& params, const DiscreteModel& model,
                                     int integer_bits, int fraction_bits, int tick_level,
                                     ParameterUnits units) noexcept;

}  // namespace stickslip
