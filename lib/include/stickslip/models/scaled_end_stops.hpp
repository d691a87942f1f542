// The seat with end stops in scene units (models/scaled_oscillator.hpp): time in steps, mass in
// seat masses, length in a unit L chosen from the declared ranges, for a 32-bit fixed-point scalar
// (Q7.24). The stops scale as the seat does: travel' = travel / L, k_s' = k_s dt^2 / m,
// b_s' = b_s dt / m. L is the larger of the units the free seat and the seat in contact (k + k_s,
// b + b_s, whose forces at the displacement range bound the stop's) would choose, so that what the
// step forms in either mode stays within a quarter of the format. The same EndStopOscillator
// source runs on the scaled parameters, with one tick per step and the cubic polynomial of the
// exact solution inside it (ScalarTraits::kCubicEventSearch); only the boundary converts.
#pragma once

#include <cmath>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/scaled_oscillator.hpp"

namespace stickslip {

// The units for the seat `si` with the stops `stops` (validated by the caller), whose largest
// range quantity is `limit` in scene units; L = 0 where none fits (the configure refuses).
inline SceneUnits choose_end_stop_scene_units(const OscillatorParams& si,
                                              const EndStopParams& stops, double limit) noexcept {
  SceneUnits units = choose_scene_units(si, limit);
  const SceneUnits in_contact = choose_scene_units(contact_seat(si, stops), limit);
  if (units.length_m == 0.0 || in_contact.length_m == 0.0) {
    units.length_m = 0.0;
  } else {
    units.length_m = std::fmax(units.length_m, in_contact.length_m);
  }
  return units;
}

// `stops` expressed in the scene units `u`.
inline EndStopParams to_scene_units(const EndStopParams& stops, const SceneUnits& u) noexcept {
  EndStopParams p;
  p.travel_m = stops.travel_m / u.length_m;
  p.stiffness_n_per_m = stops.stiffness_n_per_m * u.time_s * u.time_s / u.mass_kg;
  p.damping_ns_per_m = stops.damping_ns_per_m * u.time_s / u.mass_kg;
  return p;
}

template <typename T, typename Law>
class ScaledEndStopOscillator {
  using S = ScalarTraits<T>;

 public:
  using Scalar = T;
  using FrictionLaw = Law;

  // Validates in SI (messages name the SI parameter), chooses the units, then configures the
  // model on the scaled parameters; a refusal there gives the scaled quantity and the unit L.
  ConfigResult configure(const OscillatorParams& si, const EndStopParams& stops) noexcept {
    DiscreteModel free_model, contact_model;
    ConfigResult result = check_end_stops(si, stops, free_model, contact_model);
    if (!result.ok()) return result;
    units_ = choose_end_stop_scene_units(
        si, stops, std::ldexp(1.0, T::kIntegerBits - kFixedPointHeadroomBits));
    if (units_.length_m == 0.0) {
      result = refusal(Status::out_of_range);
      result.message.append("displacement_range_m: the ranges give no length unit");
      return result;
    }
    result = model_.configure(to_scene_units(si, units_), to_scene_units(stops, units_));
    if (!result.ok()) name_scene_units(result, units_);
    return result;
  }

  const SceneUnits& units() const noexcept { return units_; }
  // The model with stops (ScaledOscillator's accessor, by the same name).
  EndStopOscillator<T, Law>& oscillator() noexcept { return model_; }
  const EndStopOscillator<T, Law>& oscillator() const noexcept { return model_; }

  // The input a_u in units of units().acceleration_m_per_s2(); outputs in scene units.
  StepOutput<T> step(T a_u_scaled) noexcept { return model_.step(a_u_scaled); }
  void step(T a_u_scaled, StepOutput<T>& out) noexcept { out = model_.step(a_u_scaled); }

 private:
  EndStopOscillator<T, Law> model_;
  SceneUnits units_;
};

}  // namespace stickslip
