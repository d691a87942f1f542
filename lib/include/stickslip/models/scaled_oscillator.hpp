// The oscillator in scene units: time in steps, mass in seat masses, length in a unit L chosen
// from the declared ranges, so that every quantity the step forms is O(1) and a 32-bit fixed-point
// scalar (core/fixed_point32.hpp) holds it with ~24 significant bits.
//
// The physics is unit-free: m' dv'/dt' + b' v' + k' x' + F' = -m' a', with
//   m' = 1, k' = k dt^2/m, b' = b dt/m, F' = F dt^2/(m L), dt' = 1,
//   x' = x/L, v' = v dt/L, a' = a dt^2/L, c' = c L/dt (rational smoothing), v_S' = v_S dt/L.
// The same Oscillator<T, Law> source runs on the scaled parameters; only the boundary converts.
// L is the smallest length for which the declared ranges (OscillatorParams::input_range_m_per_s2,
// displacement_range_m) and what the step forms at them stay within a quarter of the format's
// range, which leaves the most fraction bits to everything else. configure() then checks every
// coefficient's precision as for Q23.40 (integrators/fixed_point_scaling.hpp) and refuses, naming
// the parameter, a scene the format cannot hold (e.g. a friction force below 2^-14 of the range).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "stickslip/core/fixed_point.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/integrators/fixed_point_scaling.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip {

// The units of a scaled scene, in SI.
struct SceneUnits {
  double time_s = 1.0;    // dt
  double mass_kg = 1.0;   // m
  double length_m = 1.0;  // L
  double velocity_m_per_s() const noexcept { return length_m / time_s; }
  double acceleration_m_per_s2() const noexcept { return length_m / (time_s * time_s); }
  double force_n() const noexcept { return mass_kg * acceleration_m_per_s2(); }
};

// The units for `si` (validated by the caller's configure) whose largest range quantity is
// `limit` (in scene units). Non-finite or non-positive inputs give L = 0 (the configure refuses).
inline SceneUnits choose_scene_units(const OscillatorParams& si, double limit) noexcept {
  SceneUnits u;
  u.time_s = si.dt_s;
  u.mass_kg = si.mass_kg;
  const double dt = si.dt_s;
  const double x = si.displacement_range_m, a = si.input_range_m_per_s2;
  const double omega0 = std::sqrt(si.stiffness_n_per_m / si.mass_kg);
  const double v = omega0 * x + a / omega0;  // the bound check_fixed_point_scene uses
  const double friction = si.model == FrictionModel::linear
                              ? 0.0
                              : std::fmax(si.kinetic_friction_n, si.static_friction_n);
  // In lengths: x itself, v over a step, and the seat acceleration (the largest sum of the step's
  // accelerations) over a step squared.
  const double seat =
      (si.stiffness_n_per_m * x + si.damping_ns_per_m * v + friction) / si.mass_kg + a;
  double largest = x;
  largest = std::fmax(largest, v * dt);
  largest = std::fmax(largest, seat * dt * dt);
  u.length_m = largest / limit;
  if (!(std::isfinite(u.length_m) && u.length_m > 0.0)) u.length_m = 0.0;
  return u;
}

// `si` expressed in the scene units `u`.
inline OscillatorParams to_scene_units(const OscillatorParams& si, const SceneUnits& u) noexcept {
  OscillatorParams p = si;
  const double t = u.time_s, m = u.mass_kg, l = u.length_m;
  p.mass_kg = si.mass_kg / m;
  p.stiffness_n_per_m = si.stiffness_n_per_m * t * t / m;
  p.damping_ns_per_m = si.damping_ns_per_m * t / m;
  p.kinetic_friction_n = si.kinetic_friction_n / u.force_n();
  p.static_friction_n = si.static_friction_n / u.force_n();
  p.stribeck_velocity_m_per_s = si.stribeck_velocity_m_per_s / u.velocity_m_per_s();
  p.smoothing_constant_s_per_m = si.smoothing_constant_s_per_m * u.velocity_m_per_s();
  p.dt_s = si.dt_s / t;
  p.input_range_m_per_s2 = si.input_range_m_per_s2 / u.acceleration_m_per_s2();
  p.displacement_range_m = si.displacement_range_m / l;
  return p;
}

// An integer count of some SI unit (a CAN signal's raw value, say) to a fixed-point scalar in
// scene units, or back: one 32 x 32 -> 64-bit product and a rounding shift. The factor (1e-3
// m/s^2 / (L/dt^2) = 3.3e-7 for a_u in mm/s^2) is far below the scalar's resolution, so it is not
// a scalar itself; it keeps 24 significant bits (relative error <= 2^-25).
template <typename T>
class CountScale {
 public:
  // to_scalar(count) = count * factor, in T's units. False unless the factor is finite and the
  // shift it needs is in [1, 62] (factor in [2^-38 2^-F, 2^-F) for T with F fraction bits).
  bool set_count_to_scalar(double factor) noexcept { return set(factor, -T::kFractionBits); }
  // to_count(value) = value * factor, in counts; factor in [2^-38 2^F, 2^F).
  bool set_scalar_to_count(double factor) noexcept { return set(factor, T::kFractionBits); }

  // Saturates and flags like any conversion.
  T to_scalar(std::int32_t count) const noexcept {
    return T::from_raw(saturate(rounded_product(count)));
  }
  // Rounded to nearest (ties away from zero), clamped to [-limit, limit].
  std::int32_t to_count(T value, std::int32_t limit) const noexcept {
    const std::int64_t count = rounded_product(value.raw());
    return static_cast<std::int32_t>(count > limit ? limit : (count < -limit ? -limit : count));
  }

 private:
  bool set(double factor, int extra_shift) noexcept {
    if (!(std::isfinite(factor) && factor > 0.0)) return false;
    int exponent = 0;
    const double mantissa = std::frexp(factor, &exponent);  // factor = mantissa 2^exponent
    const int shift = 24 - exponent + extra_shift;
    if (shift < 1 || shift > 62) return false;
    // round(mantissa 2^24) is in [2^23, 2^24]: fits int32 with the product below 2^63.
    multiplier_ = static_cast<std::int32_t>(std::ldexp(mantissa, 24) + 0.5);
    shift_ = shift;
    half_ = std::uint64_t{1} << (shift - 1);
    return true;
  }
  // round(v multiplier / 2^shift), ties away from zero.
  STICKSLIP_OUT_OF_LINE std::int64_t rounded_product(std::int32_t v) const noexcept {
    // |v| <= 2^31 and the multiplier < 2^25: a 32 x 32-bit product (no 64-bit library
    // multiply on ARMv6-M).
    const auto magnitude = fixed_point_detail::multiply_32x32(
        static_cast<std::uint32_t>(v < 0 ? -std::int64_t{v} : std::int64_t{v}),
        static_cast<std::uint32_t>(multiplier_));
    const auto q = static_cast<std::int64_t>(shift_right(magnitude + half_, shift_));
    return v < 0 ? -q : q;
  }
  // a >> shift for shift in [1, 62] in 32-bit halves: a 64-bit shift by a variable amount is a
  // library call on ARMv6-M (two per conversion, five conversions per sample on the Cortex-M0+).
  static std::uint64_t shift_right(std::uint64_t a, int shift) noexcept {
    const auto high = static_cast<std::uint32_t>(a >> 32);
    const auto low = static_cast<std::uint32_t>(a);
    if (shift >= 32) return high >> (shift - 32);
    return (std::uint64_t{high >> shift} << 32) | (low >> shift) | (high << (32 - shift));
  }
  static typename T::Raw saturate(std::int64_t v) noexcept {
    using Raw = typename T::Raw;
    constexpr auto max = static_cast<std::int64_t>(
        static_cast<std::make_unsigned_t<Raw>>(~std::make_unsigned_t<Raw>{0}) >> 1);
    if (v > max || v < -max) {
      fixed_point_detail::flag_saturation();
      return static_cast<Raw>(v > 0 ? max : -max);
    }
    return static_cast<Raw>(v);
  }
  std::int32_t multiplier_ = 0;
  int shift_ = 1;
  std::uint64_t half_ = 1;  // 2^(shift_ - 1): rounds to nearest
};

// A refusal of a model configured in scene units ("<parameter>: <quantity> = <value in scene
// units> ..."), made to say which units they are and what sets L.
inline void name_scene_units(ConfigResult& result, const SceneUnits& units) noexcept {
  const StatusMessage inner = result.message;
  const char* text = inner.c_str();
  const char* colon = text;
  while (*colon != '\0' && !(colon[0] == ':' && colon[1] == ' ')) ++colon;
  result.message.clear();
  if (*colon == '\0') {
    result.message.append(text);
    return;
  }
  char parameter[48] = {};
  for (std::size_t i = 0; i + 1 < sizeof parameter && text + i != colon + 2; ++i)
    parameter[i] = text[i];
  result.message.append(parameter);
  result.message.append("in scene units (time dt, mass m, length L = ")
      .append(units.length_m)
      .append(" m, set by displacement_range_m and input_range_m_per_s2), ")
      .append(colon + 2);
}

template <typename T, typename Law>
class ScaledOscillator {
  using S = ScalarTraits<T>;

 public:
  using Scalar = T;
  using FrictionLaw = Law;

  // Chooses the units for `si` (in SI), then configures the oscillator on the scaled parameters.
  // A refusal names the SI parameter; its message gives the scaled quantity and the unit L.
  ConfigResult configure(const OscillatorParams& si) noexcept {
    DiscreteModel model;
    ConfigResult result = discretise(si, model);  // SI validation first, with SI messages
    if (!result.ok()) return result;
    units_ = choose_scene_units(si, std::ldexp(1.0, T::kIntegerBits - kFixedPointHeadroomBits));
    if (units_.length_m == 0.0) {
      result = refusal(Status::out_of_range);
      result.message.append("displacement_range_m: the ranges give no length unit");
      return result;
    }
    result = oscillator_.configure(to_scene_units(si, units_));
    if (!result.ok()) name_scene_units(result, units_);
    return result;
  }

  const SceneUnits& units() const noexcept { return units_; }
  Oscillator<T, Law>& oscillator() noexcept { return oscillator_; }
  const Oscillator<T, Law>& oscillator() const noexcept { return oscillator_; }

  // The input a_u in units of units().acceleration_m_per_s2(); outputs in scene units.
  STICKSLIP_INLINE_STEP StepOutput<T> step(T a_u_scaled) noexcept {
    return oscillator_.step(a_u_scaled);
  }
  STICKSLIP_INLINE_STEP void step(T a_u_scaled, StepOutput<T>& out) noexcept {
    oscillator_.step(a_u_scaled, out);
  }
  // With the actuator force f_a in units of units().force_n() (force() converts), held over the
  // step; the input range must cover |a_u - f_a/m| (see Oscillator::step).
  STICKSLIP_INLINE_STEP StepOutput<T> step(T a_u_scaled, T f_a_scaled) noexcept {
    return oscillator_.step(a_u_scaled, f_a_scaled);
  }
  STICKSLIP_INLINE_STEP void step(T a_u_scaled, T f_a_scaled, StepOutput<T>& out) noexcept {
    oscillator_.step(a_u_scaled, f_a_scaled, out);
  }

  // Host-side conversions (double): SI -> scene units and back.
  T acceleration(double a_m_per_s2) const noexcept {
    return S::from_double(a_m_per_s2 / units_.acceleration_m_per_s2());
  }
  T force(double f_n) const noexcept { return S::from_double(f_n / units_.force_n()); }
  double to_si_acceleration(T a) const noexcept {
    return S::to_double(a) * units_.acceleration_m_per_s2();
  }
  double to_si_displacement(T x) const noexcept { return S::to_double(x) * units_.length_m; }
  double to_si_velocity(T v) const noexcept { return S::to_double(v) * units_.velocity_m_per_s(); }
  double to_si_force(T f) const noexcept { return S::to_double(f) * units_.force_n(); }
  double to_si_time(T t) const noexcept { return S::to_double(t) * units_.time_s; }

 private:
  Oscillator<T, Law> oscillator_;
  SceneUnits units_;
};

}  // namespace stickslip
