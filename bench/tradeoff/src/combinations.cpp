#include "tradeoff/combinations.hpp"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff {
namespace {

std::vector<std::string> split(const std::string& what, const std::string& list) {
  std::vector<std::string> items;
  std::string item;
  for (const char c : list + ",") {
    if (c != ',') {
      if (c != ' ') item += c;
      continue;
    }
    if (!item.empty()) items.push_back(item);
    item.clear();
  }
  if (items.empty()) throw host::UsageError(fmt::format("{}: the list is empty", what));
  return items;
}

double parse_number(const std::string& what, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
    throw host::UsageError(fmt::format("{}: '{}' is not a number", what, text));
  }
  return value;
}

constexpr const char* kModelNames =
    "linear, signum, smooth (= smooth-tanh), smooth-tanh, smooth-atan, smooth-erf, "
    "smooth-rational, stick-slip, stribeck";

}  // namespace

const char* peer_integrator_name(PeerKind kind) noexcept {
  switch (kind) {
    case PeerKind::rk4_smooth:
      return "odeint-rk4";
    case PeerKind::dopri5_smooth:
      return "odeint-dopri5";
    case PeerKind::dopri5_events:
      return "odeint-dopri5-events";
  }
  return "?";
}

const char* peer_model_name(PeerKind kind) noexcept {
  return kind == PeerKind::dopri5_events ? "stick-slip" : "smooth-tanh";
}

bool peer_uses_tolerance(PeerKind kind) noexcept {
  return kind != PeerKind::rk4_smooth;
}

std::vector<ModelChoice> parse_models(const std::string& list) {
  std::vector<ModelChoice> out;
  for (const std::string& name : split("--models", list)) {
    ModelChoice choice;
    choice.name = name;
    if (name == "smooth") choice.name = "smooth-tanh";
    if (choice.name.rfind("smooth-", 0) == 0) {
      choice.model = FrictionModel::smooth;
      if (!parse_smoothing(choice.name.c_str() + 7, choice.smoothing)) {
        throw host::UsageError(
            fmt::format("--models: unknown model '{}' (known: {})", name, kModelNames));
      }
    } else if (!parse_model(name.c_str(), choice.model) || choice.model == FrictionModel::smooth) {
      throw host::UsageError(
          fmt::format("--models: unknown model '{}' (known: {})", name, kModelNames));
    }
    out.push_back(choice);
  }
  return out;
}

std::vector<Integrator> parse_integrators(const std::string& list) {
  std::vector<Integrator> out;
  for (const std::string& name : split("--integrators", list)) {
    Integrator integrator{};
    if (!parse_integrator(name.c_str(), integrator)) {
      throw host::UsageError(fmt::format(
          "--integrators: unknown integrator '{}' (known: euler, symplectic, rk4, exact)", name));
    }
    out.push_back(integrator);
  }
  return out;
}

std::vector<host::ScalarType> parse_scalars(const std::string& list) {
  std::vector<host::ScalarType> out;
  for (const std::string& name : split("--scalars", list)) {
    host::ScalarType scalar{};
    if (!host::parse_scalar(name, scalar)) {
      throw host::UsageError(
          fmt::format("--scalars: unknown scalar type '{}' (known: float, double)", name));
    }
    out.push_back(scalar);
  }
  return out;
}

std::vector<double> parse_dts_ms(const std::string& list) {
  std::vector<double> out;
  for (const std::string& item : split("--dt", list)) {
    const double dt_ms = parse_number("--dt (ms)", item);
    try {
      stride_for_dt_ms(dt_ms);
    } catch (const host::UsageError& error) {
      throw host::UsageError(std::string("--dt: ") + error.what());
    }
    out.push_back(dt_ms);
  }
  return out;
}

std::vector<host::SignalKind> parse_kinds(const std::string& list) {
  std::vector<host::SignalKind> out;
  for (const std::string& name : split("--kinds", list)) {
    host::SignalKind kind{};
    if (!host::parse_signal_kind(name, kind)) {
      throw host::UsageError(fmt::format(
          "--kinds: unknown signal kind '{}' (known: wideband, lorry, harmonic)", name));
    }
    out.push_back(kind);
  }
  return out;
}

std::vector<SceneFriction> parse_frictions(const std::string& list) {
  std::vector<SceneFriction> out;
  for (const std::string& name : split("--frictions", list)) {
    if (name == "none" || name == "linear") {
      out.push_back(SceneFriction::none);
    } else if (name == "coulomb") {
      out.push_back(SceneFriction::coulomb);
    } else if (name == "stribeck") {
      out.push_back(SceneFriction::stribeck);
    } else {
      throw host::UsageError(fmt::format(
          "--frictions: unknown scene friction '{}' (known: none, coulomb, stribeck)", name));
    }
  }
  return out;
}

std::vector<double> parse_numbers(const std::string& what, const std::string& list, double min,
                                  bool min_inclusive) {
  std::vector<double> out;
  for (const std::string& item : split(what, list)) {
    const double value = parse_number(what, item);
    if (min_inclusive ? value < min : value <= min) {
      throw host::UsageError(
          fmt::format("{}: {} must be {} {:g}", what, item, min_inclusive ? ">=" : ">", min));
    }
    out.push_back(value);
  }
  return out;
}

std::vector<PeerSpec> parse_peers(const std::string& list, const std::vector<double>& tolerances) {
  std::vector<PeerSpec> out;
  if (list == "none") return out;
  for (const std::string& name : split("--peers", list)) {
    PeerKind kind{};
    if (name == "rk4") {
      kind = PeerKind::rk4_smooth;
    } else if (name == "dopri5") {
      kind = PeerKind::dopri5_smooth;
    } else if (name == "dopri5-events") {
      kind = PeerKind::dopri5_events;
    } else {
      throw host::UsageError(fmt::format(
          "--peers: unknown peer '{}' (known: rk4, dopri5, dopri5-events, or none)", name));
    }
    if (!peer_uses_tolerance(kind)) {
      out.push_back({kind, 0.0});
      continue;
    }
    for (const double tolerance : tolerances) out.push_back({kind, tolerance});
  }
  return out;
}

bool runs_in_scene(const ModelChoice& model, const Scene& scene) noexcept {
  switch (model.model) {
    case FrictionModel::linear:
      return scene.friction == SceneFriction::none;
    case FrictionModel::stribeck:
      return scene.friction == SceneFriction::stribeck;
    case FrictionModel::signum:
    case FrictionModel::smooth:
    case FrictionModel::stick_slip:
      return scene.friction == SceneFriction::coulomb;
  }
  return false;
}

bool runs_at_dt(const ModelChoice& model, double dt_ms, const Plan& plan) noexcept {
  if (model.model != FrictionModel::smooth || model.smoothing == SmoothingLaw::tanh) return true;
  for (const double other : plan.other_laws_dts_ms) {
    if (std::fabs(other - dt_ms) <= 1e-9 * dt_ms) return true;
  }
  return false;
}

OscillatorParams physics_params(const Scene& scene, double dt_ms) {
  OscillatorParams p = scene.physics;
  p.dt_s = dt_ms / 1000.0;
  p.integrator = Integrator::exact;
  return p;
}

OscillatorParams run_params(const Scene& scene, const ModelChoice& model, Integrator integrator,
                            double dt_ms) {
  OscillatorParams p = physics_params(scene, dt_ms);
  p.model = model.model;
  p.smoothing = model.smoothing;
  p.integrator = integrator;
  return p;
}

bool own_reference_differs(const Scene& scene, const ModelChoice& model) noexcept {
  return scene.friction == SceneFriction::coulomb && model.model == FrictionModel::smooth;
}

OscillatorParams own_reference_params(const Scene& scene, const ModelChoice& model, double dt_ms) {
  if (!own_reference_differs(scene, model)) return physics_params(scene, dt_ms);
  return run_params(scene, model, Integrator::exact, dt_ms);
}

std::string combination_key(const std::string& scene, const std::string& model,
                            const std::string& integrator, const std::string& scalar,
                            double dt_ms) {
  return fmt::format("{}|{}|{}|{}|{:g}", scene, model, integrator, scalar, dt_ms);
}

}  // namespace stickslip::tradeoff
