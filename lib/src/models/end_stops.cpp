#include "stickslip/models/end_stops.hpp"

#include <cmath>

namespace stickslip {
namespace {

constexpr double kMaxMagnitude = 1e9;  // the bound discretise() applies to every parameter

ConfigResult refuse(Status status, const char* name, double value, const char* why) noexcept {
  ConfigResult r = refusal(status);
  r.message.append(name).append(" = ").append(value).append(why);
  return r;
}

}  // namespace

ConfigResult check_end_stops(const OscillatorParams& seat, const EndStopParams& stops,
                             DiscreteModel& free_model, DiscreteModel& contact_model) noexcept {
  ConfigResult result = discretise(seat, free_model);
  if (!result.ok()) return result;
  const struct {
    const char* name;
    double value;
    bool zero_allowed;
  } checks[] = {{"end_stop_travel_m", stops.travel_m, false},
                {"end_stop_stiffness_n_per_m", stops.stiffness_n_per_m, false},
                {"end_stop_damping_ns_per_m", stops.damping_ns_per_m, true}};
  for (const auto& c : checks) {
    if (!std::isfinite(c.value))
      return refuse(Status::not_finite, c.name, c.value, " must be finite");
    if (c.value < 0.0 || (c.value == 0.0 && !c.zero_allowed) || c.value > kMaxMagnitude) {
      return refuse(Status::out_of_range, c.name, c.value,
                    c.zero_allowed ? " must be >= 0 and <= 1e9" : " must be > 0 and <= 1e9");
    }
  }
  // The contact seat (contact_seat()): the same checks, with the parameter named as the stop's.
  result = discretise(contact_seat(seat, stops), contact_model);
  if (!result.ok()) {
    ConfigResult named;
    named.status = result.status;
    named.message
        .append(
            "in contact with an end stop (k + end_stop_stiffness_n_per_m, "
            "b + end_stop_damping_ns_per_m): ")
        .append(result.message.c_str());
    return named;
  }
  return result;
}

template class EndStopOscillator<double, NoFriction>;
template class EndStopOscillator<double, CoulombStickSlip>;
template class EndStopOscillator<float, NoFriction>;
template class EndStopOscillator<float, CoulombStickSlip>;
template class EndStopOscillator<double, StribeckStickSlip>;
template class EndStopOscillator<float, StribeckStickSlip>;

}  // namespace stickslip
