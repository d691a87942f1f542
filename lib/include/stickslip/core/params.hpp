// Physical and numerical parameters of the seat oscillator, all in SI units.
#pragma once

#include <cstdint>

namespace stickslip {

// Friction element between seat and cab floor.
enum class FrictionModel : std::uint8_t {
  linear,      // no dry friction, spring and damper only
  signum,      // F_f = F_fk * sgn(v_r), sgn(0) = 0: cheap, chatters once the mass should stick
  smooth,      // F_f = F_fk * s(c v_r) with one of the SmoothingLaw forms
  stick_slip,  // sticks while |F_L| <= F_fs, kinetic F_fk while slipping; events inside the step
  stribeck,    // [F_fk + (F_fs - F_fk) exp(-(v_r/v_S)^2)] sgn(v_r) while slipping, stick logic as
               // above
};

enum class SmoothingLaw : std::uint8_t {
  atan,      // 2/pi * atan(c v)
  tanh,      // tanh(c v)
  erf,       // erf(c v)
  rational,  // c v / (1 + c |v|)
};

enum class Integrator : std::uint8_t {
  euler,       // explicit Euler, Simulink ode1 semantics: everything from the start of the step
  symplectic,  // semi-implicit Euler: velocity first, position with the updated velocity
  rk4,         // classic 4th-order Runge-Kutta with first-order-hold input
  exact,       // exact discretisation of the linear part (matrix exponential, first-order hold)
};

struct OscillatorParams {
  double mass_kg = 88.4;
  double stiffness_n_per_m = 11500.0;
  double damping_ns_per_m = 504.0;
  double kinetic_friction_n = 0.0;  // F_fk
  double static_friction_n = 0.0;   // F_fs >= F_fk (stick-slip and Stribeck)
  double stribeck_velocity_m_per_s = 0.01;
  SmoothingLaw smoothing = SmoothingLaw::tanh;
  double smoothing_constant_s_per_m = 1000.0;  // c in s(c v)
  double dt_s = 1e-3;
  FrictionModel model = FrictionModel::stick_slip;
  Integrator integrator = Integrator::exact;
  // Fixed point only (Oscillator<Fixed, ...>): the ranges its scaling must hold. configure()
  // refuses a scene whose values at these ranges would not fit
  // (integrators/fixed_point_scaling.hpp); beyond them a run saturates and says so
  // (Oscillator::saturated_steps()).
  double input_range_m_per_s2 = 50.0;  // largest |a_u| (with an actuator force: |a_u - f_a/m|)
  double displacement_range_m = 1.0;   // largest |x_r|
};

// The integrator `simulate` uses when none is named: the most accurate one for the model.
Integrator default_integrator(FrictionModel model) noexcept;

// Names as used on the command line and in files ("stick-slip", "rk4", ...).
const char* model_name(FrictionModel model) noexcept;
const char* smoothing_name(SmoothingLaw law) noexcept;
const char* integrator_name(Integrator integrator) noexcept;
bool parse_model(const char* name, FrictionModel& out) noexcept;
bool parse_smoothing(const char* name, SmoothingLaw& out) noexcept;
bool parse_integrator(const char* name, Integrator& out) noexcept;

}  // namespace stickslip
