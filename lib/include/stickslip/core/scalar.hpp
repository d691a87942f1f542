// The few scalar operations the step needs, behind one trait so that a fixed-point type can
// provide its own (the step never calls std:: math directly).
#pragma once

#include <cmath>
#include <limits>

// The step's rare paths (event search) are kept out of line so that its common path stays small
// enough to be inlined into the caller's sample loop (no call, no StepOutput through memory).
// The per-sample step itself is always inlined (a call would pass StepOutput through memory).
#if defined(__GNUC__) || defined(__clang__)
#define STICKSLIP_OUT_OF_LINE __attribute__((noinline))
#define STICKSLIP_INLINE_STEP __attribute__((always_inline)) inline
#else
#define STICKSLIP_OUT_OF_LINE
#define STICKSLIP_INLINE_STEP inline
#endif

// Size-optimised builds (the MCU presets) fold the event search's bisection loop into the event
// loop of the step: one stack frame instead of two nested ones (the M0+ stack budget).
#if defined(__OPTIMIZE_SIZE__) && (defined(__GNUC__) || defined(__clang__))
#define STICKSLIP_COMPACT_INLINE __attribute__((always_inline)) inline
#else
#define STICKSLIP_COMPACT_INLINE
#endif

namespace stickslip {

template <typename T>
struct ScalarTraits;

template <typename Float>
struct FloatScalarTraits {
  // The exact integrator's event search solves the Taylor polynomial inside a tick (a fixed-point
  // scalar bisects and interpolates, or solves a cubic over the whole step, instead).
  static constexpr bool kTaylorEventSearch = true;
  // One tick per step with the cubic polynomial inside it: fixed point in scene units only.
  static constexpr bool kCubicEventSearch = false;
  // Parameters in SI units (scene units, dt = 1 and m = 1: Q7.24 only).
  static constexpr bool kSceneUnits = false;
  // Saturation cannot happen: IEEE overflow gives Inf, which the step's guards handle.
  static constexpr bool kTracksSaturation = false;
  // The common path's whole slipping step stays inline (no call: the host's speed).
  static constexpr bool kCompactStack = false;
  static constexpr Float from_double(double value) noexcept { return static_cast<Float>(value); }
  static constexpr double to_double(Float value) noexcept { return static_cast<double>(value); }
  static bool is_finite(Float value) noexcept { return std::isfinite(value); }
  // A sign-bit mask, not a compare and branch: |F_L| is tested every stuck step, and the sign
  // of F_L is data, which a branch predictor cannot learn.
  static Float abs(Float value) noexcept { return std::fabs(value); }
  static constexpr Float epsilon() noexcept { return std::numeric_limits<Float>::epsilon(); }
  // The in-step event instants n/d (0 <= n/d <= 1 by construction): a plain division here; a
  // fixed-point scalar finds it by shift-and-subtract.
  static Float proportion(Float n, Float d) noexcept { return n / d; }
  // v / 2^shift: exact in floating point.
  static Float divide_by_power_of_two(Float v, int shift) noexcept { return std::ldexp(v, -shift); }
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
