#include "stickslip/host/run/stats_json.hpp"

#include <nlohmann/json.hpp>

#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip::host {

std::string format_stats_json(const SimulationSummary& s, const StatsContext& context) {
  const OscillatorParams& p = context.setup->params;
  nlohmann::ordered_json json;  // keeps the contract keys first, in this order
  json["samples"] = s.samples;
  json["dt"] = s.dt_s;
  json["rms_u"] = s.rms_u;
  json["rms_x"] = s.rms_x;
  json["T_ax"] = s.transmissibility;
  json["p_stick"] = s.stick_probability;
  json["K"] = s.den_hartog_k;  // +inf (no excitation) is dumped as null
  json["ns_per_sample"] = s.ns_per_sample;
  json["steps"] = s.steps;
  json["model"] = model_name(p.model);
  json["integrator"] = integrator_name(p.integrator);
  json["scalar"] = scalar_name(context.scalar);
  json["regime"] = regime_name(friction_regime(s.den_hartog_k));
  json["mass"] = p.mass_kg;
  json["stiffness"] = p.stiffness_n_per_m;
  json["damping"] = p.damping_ns_per_m;
  json["ffk"] = p.kinetic_friction_n;
  json["ffs"] = p.static_friction_n;
  if (p.model == FrictionModel::stribeck) json["stribeck_velocity"] = p.stribeck_velocity_m_per_s;
  if (p.model == FrictionModel::smooth) {
    json["smoothing"] = smoothing_name(p.smoothing);
    json["smoothing_c"] = p.smoothing_constant_s_per_m;
  }
  json["x0"] = context.setup->x0_m;
  json["v0"] = context.setup->v0_m_per_s;
  json["events"] = s.events;
  json["rejected_inputs"] = s.rejected_inputs;
  json["event_budget_exhausted"] = s.event_budget_exhausted;
  json["state_resets"] = s.state_resets;
  if (s.end_stops) json["end_stop_contacts"] = s.end_stop_contacts;
  if (context.scalar == ScalarType::fixed || context.scalar == ScalarType::fixed32) {
    // Fixed point: whether any value saturated (clipped, never wrapped), and in how many steps.
    json["saturation"] = s.saturated_steps != 0;
    json["saturated_steps"] = s.saturated_steps;
  }
  if (s.comfort) {  // ISO 2631-1, Wk: the seat's vertical axis
    json["seat_weighted_rms"] = s.seat_weighted_rms;
    json["floor_weighted_rms"] = s.floor_weighted_rms;
    json["seat"] = s.seat_ratio;
    json["vdv"] = s.seat_vdv;
    json["mtvv"] = s.seat_mtvv;
    json["crest_factor"] = s.seat_crest_factor;
  }
  if (s.observed) {
    nlohmann::ordered_json observer;
    observer["window_s"] = s.window_s;
    observer["T_ax"] = s.window_transmissibility;
    observer["p_stick"] = s.window_stick_probability;
    observer["K"] = s.window_den_hartog_k;
    observer["stick_events"] = s.window_stick_events;
    observer["slip_events"] = s.window_slip_events;
    observer["regime"] = s.observer_regime;
    observer["regime_changes"] = s.regime_changes;
    json["observer"] = observer;
  }
  json["repetitions"] = s.repetitions;
  json["input"] = context.input_path;
  json["output"] = context.output_path;
  // Replace, not throw, should a file name hold invalid UTF-8.
  return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace stickslip::host
