// The few scalar operations the step needs, behind one trait so that a fixed-point type can
// provide its own (the step never calls std:: math directly).
#pragma once

#include <cmath>

namespace stickslip {

template <typename T>
struct ScalarTraits;

template <typename Float>
struct FloatScalarTraits {
  static constexpr Float from_double(double value) noexcept { return static_cast<Float>(value); }
  static constexpr double to_double(Float value) noexcept { return static_cast<double>(value); }
  static bool is_finite(Float value) noexcept { return std::isfinite(value); }
  static constexpr Float abs(Float value) noexcept { return value < Float(0) ? -value : value; }
  // Transcendentals used only by the friction laws that need them (smoothed signum, Stribeck).
  static Float tanh(Float value) noexcept { return std::tanh(value); }
  static Float atan(Float value) noexcept { return std::atan(value); }
  static Float erf(Float value) noexcept { return std::erf(value); }
  static Float exp(Float value) noexcept { return std::exp(value); }
};

template <>
struct ScalarTraits<float> : FloatScalarTraits<float> {};
template <>
struct ScalarTraits<double> : FloatScalarTraits<double> {};

// sgn with sgn(0) = 0, as the signum friction law defines it.
template <typename T>
constexpr T signum(T value) noexcept {
  return value > T(0) ? T(1) : (value < T(0) ? T(-1) : T(0));
}

}  // namespace stickslip
