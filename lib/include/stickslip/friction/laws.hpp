// Friction laws as compile-time policies: the oscillator's step is instantiated for exactly one
// law, so a scene pays only for the friction it names.
#pragma once

#include <limits>
#include <type_traits>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"

namespace stickslip {

// How a law enters the step.
enum class LawKind : unsigned char {
  none,      // linear: no friction at all
  held,      // a function of v_r alone (signum, smoothed forms); no stick state
  sticking,  // stick-slip logic: stuck while |F_L| <= F_fs, events located inside the step
};

template <typename T>
struct FrictionCoefficients {
  T kinetic_n;                 // F_fk
  T static_n;                  // F_fs
  T stribeck_excess_n;         // F_fs - F_fk
  T inv_stribeck_velocity;     // 1/v_S, s/m
  T smoothing_c;               // c, s/m
  T smoothing_scale_n;         // F_fk (2/pi F_fk for the atan form)
  T stribeck_min_exponential;  // the least exp(-(v/v_S)^2) the Stribeck term is formed with
};

// FrictionCoefficients::stribeck_min_exponential for the excess F_fs - F_fk: where the excess is
// so small that excess exp(-(v/v_S)^2) would leave T's normal numbers (float: an excess below
// about 4e-3 N at v = 9 v_S, where the law stops the exponential's decay), the term stays at
// twice the smallest normal, a force far below the rounding of any F_fk; 0 (no limit) otherwise,
// and for fixed point, which has no subnormals. Every seat with an excess above that keeps the
// law's values bit for bit.
template <typename T>
T stribeck_min_exponential(double excess_n) noexcept {
  if constexpr (std::is_floating_point_v<T>) {
    constexpr double kExp81 = 1.5060973145850306e35;  // e^81: the law's exponential is >= e^-81
    const double smallest_term_n = 2.0 * static_cast<double>(std::numeric_limits<T>::min());
    if (excess_n > 0.0 && excess_n < smallest_term_n * kExp81) {
      const double least = smallest_term_n / excess_n;  // above e^-81: a normal number in T
      return static_cast<T>(least < 1.0 ? least : 1.0);
    }
  }
  (void)excess_n;
  return T(0);
}

// Every law offers the same functions so that the oscillator can be instantiated uniformly:
//   force(v, c):                 F_f as a function of v_r while moving;
//   slip_force(v, direction, c): F_f while slipping in `direction` (+1/-1), for sticking laws;
//   force_at_rest(F_L, c):       F_f at an instant where v_r = 0 under the load F_L (held laws).

struct NoFriction {
  static constexpr FrictionModel model = FrictionModel::linear;
  static constexpr LawKind kind = LawKind::none;
  static constexpr bool velocity_dependent = false;
  template <typename T>
  static T force(T /*v*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);
  }
  template <typename T>
  static T slip_force(T /*v*/, T /*direction*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);
  }
  template <typename T>
  static T force_at_rest(T /*limit_force_n*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);
  }
};

// F_f = F_fk sgn(v_r), sgn(0) = 0.
struct SignumFriction {
  static constexpr FrictionModel model = FrictionModel::signum;
  static constexpr LawKind kind = LawKind::held;
  static constexpr bool velocity_dependent = true;
  template <typename T>
  static T force(T v, const FrictionCoefficients<T>& c) noexcept {
    return c.kinetic_n * signum(v);
  }
  template <typename T>
  static T slip_force(T v, T /*direction*/, const FrictionCoefficients<T>& c) noexcept {
    return force(v, c);
  }
  // At v_r = 0 sgn is set-valued, F_f in [-F_fk, F_fk] (Filippov): the friction takes the load
  // F_L when it can hold it, else F_fk against the motion the load starts.
  template <typename T>
  static T force_at_rest(T limit_force_n, const FrictionCoefficients<T>& c) noexcept {
    if (limit_force_n > c.kinetic_n) return c.kinetic_n;
    if (limit_force_n < -c.kinetic_n) return -c.kinetic_n;
    return limit_force_n;
  }
};

// F_f = F_fk s(c v_r) for the four smoothed forms of the signum.
template <SmoothingLaw Law>
struct SmoothFriction {
  static constexpr FrictionModel model = FrictionModel::smooth;
  static constexpr SmoothingLaw smoothing = Law;
  static constexpr LawKind kind = LawKind::held;
  static constexpr bool velocity_dependent = true;
  template <typename T>
  static T force(T v, const FrictionCoefficients<T>& c) noexcept {
    using S = ScalarTraits<T>;
    const T cv = c.smoothing_c * v;
    if constexpr (Law == SmoothingLaw::atan) {
      return c.smoothing_scale_n * S::atan(cv);  // scale = 2/pi F_fk, set in configure
    } else if constexpr (Law == SmoothingLaw::tanh) {
      return c.smoothing_scale_n * S::tanh(cv);
    } else if constexpr (Law == SmoothingLaw::erf) {
      return c.smoothing_scale_n * S::erf(cv);
    } else {
      return c.smoothing_scale_n * cv / (T(1) + S::abs(cv));  // the law's own division
    }
  }
  template <typename T>
  static T slip_force(T v, T /*direction*/, const FrictionCoefficients<T>& c) noexcept {
    return force(v, c);
  }
  // A continuous law is single-valued at rest: F_f(0) = 0.
  template <typename T>
  static T force_at_rest(T /*limit_force_n*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);
  }
};

// Coulomb stick-slip: kinetic F_fk while slipping in direction `direction` (+1 or -1).
struct CoulombStickSlip {
  static constexpr FrictionModel model = FrictionModel::stick_slip;
  static constexpr LawKind kind = LawKind::sticking;
  static constexpr bool velocity_dependent = false;
  template <typename T>
  static T slip_force(T /*v*/, T direction, const FrictionCoefficients<T>& c) noexcept {
    return c.kinetic_n * direction;
  }
  template <typename T>
  static T force(T v, const FrictionCoefficients<T>& c) noexcept {
    return slip_force(v, signum(v), c);
  }
  template <typename T>
  static T force_at_rest(T /*limit_force_n*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);  // sticking laws decide at rest with their own stick logic
  }
};

// Stribeck (Gaussian) law while slipping, with the same stick logic.
struct StribeckStickSlip {
  static constexpr FrictionModel model = FrictionModel::stribeck;
  static constexpr LawKind kind = LawKind::sticking;
  static constexpr bool velocity_dependent = true;
  template <typename T>
  static T slip_force(T v, T direction, const FrictionCoefficients<T>& c) noexcept {
    using S = ScalarTraits<T>;
    // Square the scaled velocity v/v_S, not v itself (v^2 underflows in float near v = 0);
    // below 1e-9 the exponential is 1 to any precision, and exp(-81) is negligible against F_fk;
    // with the least exponential a small excess is formed with (stribeck_min_exponential()), the
    // clamps keep every intermediate a normal number.
    T scaled = ScalarTraits<T>::abs(v) * c.inv_stribeck_velocity;
    if (scaled < T(1e-9)) scaled = T(0);
    if (scaled > T(9)) scaled = T(9);
    const T exponent = scaled * scaled;
    T exponential = S::exp(-exponent);
    if (exponential < c.stribeck_min_exponential) exponential = c.stribeck_min_exponential;
    const T magnitude = c.kinetic_n + c.stribeck_excess_n * exponential;
    return magnitude * direction;
  }
  template <typename T>
  static T force(T v, const FrictionCoefficients<T>& c) noexcept {
    return slip_force(v, signum(v), c);
  }
  template <typename T>
  static T force_at_rest(T /*limit_force_n*/, const FrictionCoefficients<T>& /*c*/) noexcept {
    return T(0);  // sticking laws decide at rest with their own stick logic
  }
};

}  // namespace stickslip
