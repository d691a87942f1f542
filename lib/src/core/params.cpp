#include "stickslip/core/params.hpp"

#include <cstring>

namespace stickslip {

Integrator default_integrator(FrictionModel model) noexcept {
  switch (model) {
    case FrictionModel::smooth:
    case FrictionModel::stribeck:
      return Integrator::rk4;  // velocity-dependent friction: stage evaluation is the most accurate
    case FrictionModel::linear:
    case FrictionModel::signum:
    case FrictionModel::stick_slip:
      break;
  }
  return Integrator::exact;
}

const char* model_name(FrictionModel model) noexcept {
  switch (model) {
    case FrictionModel::linear:
      return "linear";
    case FrictionModel::signum:
      return "signum";
    case FrictionModel::smooth:
      return "smooth";
    case FrictionModel::stick_slip:
      return "stick-slip";
    case FrictionModel::stribeck:
      return "stribeck";
  }
  return "?";
}

const char* smoothing_name(SmoothingLaw law) noexcept {
  switch (law) {
    case SmoothingLaw::atan:
      return "atan";
    case SmoothingLaw::tanh:
      return "tanh";
    case SmoothingLaw::erf:
      return "erf";
    case SmoothingLaw::rational:
      return "rational";
  }
  return "?";
}

const char* integrator_name(Integrator integrator) noexcept {
  switch (integrator) {
    case Integrator::euler:
      return "euler";
    case Integrator::symplectic:
      return "symplectic";
    case Integrator::rk4:
      return "rk4";
    case Integrator::exact:
      return "exact";
  }
  return "?";
}

namespace {
template <typename Enum, int Count, typename NameFn>
bool parse_by_name(const char* name, Enum& out, NameFn name_of) noexcept {
  if (name == nullptr) return false;
  for (int i = 0; i < Count; ++i) {
    const Enum candidate = static_cast<Enum>(i);
    if (std::strcmp(name, name_of(candidate)) == 0) {
      out = candidate;
      return true;
    }
  }
  return false;
}
}  // namespace

bool parse_model(const char* name, FrictionModel& out) noexcept {
  return parse_by_name<FrictionModel, 5>(name, out, model_name);
}
bool parse_smoothing(const char* name, SmoothingLaw& out) noexcept {
  return parse_by_name<SmoothingLaw, 4>(name, out, smoothing_name);
}
bool parse_integrator(const char* name, Integrator& out) noexcept {
  return parse_by_name<Integrator, 4>(name, out, integrator_name);
}

}  // namespace stickslip
