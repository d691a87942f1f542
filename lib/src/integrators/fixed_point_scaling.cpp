#include "stickslip/integrators/fixed_point_scaling.hpp"

#include <cmath>
#include <cstring>
#include <initializer_list>
#include <utility>

namespace stickslip {
namespace {

// An SI unit as the scene units of a ScaledOscillator state it (time dt, mass m, length L). The
// names are arrays, not pointers, so that the table is constant data in flash on an MCU, not an
// array of addresses copied to RAM.
struct UnitName {
  char si[8];
  char scene[12];
};
const char* scene_unit(const char* si) noexcept {
  static constexpr UnitName kUnits[] = {{"kg", "m"},         {"1/kg", "1/m"},    {"N/m", "m/dt^2"},
                                        {"1/s^2", "1/dt^2"}, {"N s/m", "m/dt"},  {"1/s", "1/dt"},
                                        {"N", "m L/dt^2"},   {"s/m", "dt/L"},    {"s", "dt"},
                                        {"s^2", "dt^2"},     {"m/s^2", "L/dt^2"}};
  for (const UnitName& unit : kUnits) {
    if (std::strcmp(unit.si, si) == 0) return unit.scene;
  }
  return si;
}

struct Checker {
  double largest;   // magnitude allowed
  double smallest;  // smallest non-zero magnitude allowed
  const char* format;
  ParameterUnits units;
  ConfigResult& result;

  const char* unit_of(const char* si) const noexcept {
    return units == ParameterUnits::scene ? scene_unit(si) : si;
  }

  bool refuse(Status status, const char* parameter) {
    result = refusal(status);
    result.message.append(parameter).append(": ");
    return false;
  }
  // `quantity` (what the step forms) at `value` must be <= largest.
  bool fits(const char* parameter, const char* quantity, double value, const char* unit) {
    if (std::fabs(value) <= largest) return true;
    refuse(Status::out_of_range, parameter);
    result.message.append(quantity)
        .append(" = ")
        .append(value)
        .append(" ")
        .append(unit_of(unit))
        .append(" does not fit the fixed-point scalar ")
        .append(format)
        .append(" (|value| <= ")
        .append(largest)
        .append(")");
    return false;
  }
  // A non-zero coefficient must be >= smallest (it keeps 11 significant bits).
  bool resolved(const char* parameter, const char* quantity, double value, const char* unit) {
    if (value == 0.0 || std::fabs(value) >= smallest) return true;
    refuse(Status::out_of_range, parameter);
    result.message.append(quantity)
        .append(" = ")
        .append(value)
        .append(" ")
        .append(unit_of(unit))
        .append(" is below the precision of the fixed-point scalar ")
        .append(format)
        .append(" (needs |value| >= ")
        .append(smallest)
        .append(")");
    return false;
  }
};

// "Q<I>.<F>" without printf.
void format_name(int integer_bits, int fraction_bits, char (&format)[16]) {
  int at = 1;
  for (int value : {integer_bits, fraction_bits}) {
    if (value >= 10) format[at++] = static_cast<char>('0' + value / 10);
    format[at++] = static_cast<char>('0' + value % 10);
    format[at++] = '.';
  }
  format[at - 1] = '\0';
}

// The laws and integrators fixed point offers, and ranges it can scale to.
bool offered(const OscillatorParams& p, Checker& c) {
  ConfigResult& r = c.result;
  if (p.model == FrictionModel::stribeck) {
    c.refuse(Status::unsupported, "model");
    r.message.append("stribeck needs exp(), which the fixed-point scalar does not offer");
    return false;
  }
  if (p.model == FrictionModel::smooth && p.smoothing != SmoothingLaw::rational) {
    c.refuse(Status::unsupported, "smoothing");
    r.message.append(smoothing_name(p.smoothing))
        .append(" needs a transcendental function; fixed point offers the rational form only");
    return false;
  }
  if (p.integrator == Integrator::rk4) {
    c.refuse(Status::unsupported, "integrator");
    r.message.append("rk4 is not offered in fixed point (use exact, symplectic or euler)");
    return false;
  }
  for (const auto& range :
       {std::pair<const char*, double>{"input_range_m_per_s2", p.input_range_m_per_s2},
        std::pair<const char*, double>{"displacement_range_m", p.displacement_range_m}}) {
    if (!(std::isfinite(range.second) && range.second > 0.0)) {
      c.refuse(Status::out_of_range, range.first);
      r.message.append("must be a finite number > 0, got ").append(range.second);
      return false;
    }
  }
  return true;
}

// The parameters and the coefficients derived from them.
bool coefficients_fit(const OscillatorParams& p, const DiscreteModel& model, int tick_level,
                      Checker& c) {
  const bool friction = p.model != FrictionModel::linear;
  const bool sticking = p.model == FrictionModel::stick_slip;
  const bool rational = p.model == FrictionModel::smooth;
  return c.fits("mass_kg", "the mass m", p.mass_kg, "kg") &&
         c.fits("mass_kg", "1/m", model.inv_mass, "1/kg") &&
         c.resolved("mass_kg", "1/m", model.inv_mass, "1/kg") &&
         c.fits("stiffness_n_per_m", "the stiffness k", p.stiffness_n_per_m, "N/m") &&
         c.fits("stiffness_n_per_m", "k/m", model.stiffness_over_mass, "1/s^2") &&
         c.resolved("stiffness_n_per_m", "k/m", model.stiffness_over_mass, "1/s^2") &&
         c.fits("damping_ns_per_m", "the damping b", p.damping_ns_per_m, "N s/m") &&
         c.fits("damping_ns_per_m", "b/m", model.damping_over_mass, "1/s") &&
         c.resolved("damping_ns_per_m", "b/m", model.damping_over_mass, "1/s") &&
         (!friction || (c.fits("kinetic_friction_n", "F_fk", p.kinetic_friction_n, "N") &&
                        c.resolved("kinetic_friction_n", "F_fk", p.kinetic_friction_n, "N"))) &&
         (!sticking || (c.fits("static_friction_n", "F_fs", p.static_friction_n, "N") &&
                        c.resolved("static_friction_n", "F_fs", p.static_friction_n, "N"))) &&
         (!rational ||
          (c.fits("smoothing_constant_s_per_m", "c", p.smoothing_constant_s_per_m, "s/m") &&
           c.resolved("smoothing_constant_s_per_m", "c", p.smoothing_constant_s_per_m, "s/m"))) &&
         c.fits("dt_s", "1/dt", model.inv_dt, "1/s") && c.resolved("dt_s", "dt", p.dt_s, "s") &&
         (tick_level < 0 || tick_level > kEventLevels ||
          c.resolved("dt_s", "the event tick dt/2^level", model.block_s[tick_level], "s")) &&
         // The whole-step map (the common path): every non-zero coefficient keeps its precision.
         c.resolved("dt_s", "the step map coefficient xv (v_r -> x_r)", model.maps[0].xv, "s") &&
         c.resolved("dt_s", "the step map coefficient vx (x_r -> v_r)", model.maps[0].vx, "1/s") &&
         c.resolved("dt_s", "the step map coefficient gx0 (input at the start -> x_r)",
                    model.maps[0].gx0, "s^2") &&
         c.resolved("dt_s", "the step map coefficient gx1 (input at the end -> x_r)",
                    model.maps[0].gx1, "s^2") &&
         c.resolved("dt_s", "the step map coefficient gv0 (input at the start -> v_r)",
                    model.maps[0].gv0, "s") &&
         c.resolved("dt_s", "the step map coefficient gv1 (input at the end -> v_r)",
                    model.maps[0].gv1, "s");
}

// What the step forms at the declared ranges.
bool intermediates_fit(const OscillatorParams& p, const DiscreteModel& model, Checker& c) {
  const bool friction = p.model != FrictionModel::linear;
  const bool sticking = p.model == FrictionModel::stick_slip;
  const bool rational = p.model == FrictionModel::smooth;
  const double a_range = p.input_range_m_per_s2;
  const double x_range = p.displacement_range_m;
  const double omega0 = model.natural_frequency_rad_s;
  const double v_range = omega0 * x_range + a_range / omega0;
  const double friction_max =
      sticking ? p.static_friction_n : (friction ? p.kinetic_friction_n : 0.0);
  return c.fits("input_range_m_per_s2", "the input force m*a_u", p.mass_kg * a_range, "N") &&
         c.fits("displacement_range_m", "the spring force k*x_r", p.stiffness_n_per_m * x_range,
                "N") &&
         c.fits("displacement_range_m", "the damper force b*v_r (v_r up to omega0*x + a/omega0)",
                p.damping_ns_per_m * v_range, "N") &&
         c.fits("input_range_m_per_s2", "the limit force m*a_u + k*x_r",
                p.mass_kg * a_range + p.stiffness_n_per_m * x_range, "N") &&
         c.fits("input_range_m_per_s2", "the seat acceleration (k x_r + b v_r + F_f)/m + a_u",
                (p.stiffness_n_per_m * x_range + p.damping_ns_per_m * v_range + friction_max) *
                        model.inv_mass +
                    a_range,
                "m/s^2") &&
         (!rational ||
          (c.fits("smoothing_constant_s_per_m", "c*v_r", p.smoothing_constant_s_per_m * v_range,
                  "1") &&
           c.fits("smoothing_constant_s_per_m", "F_fk*c*v_r",
                  model.smoothing_scale_n * p.smoothing_constant_s_per_m * v_range, "N")));
}

}  // namespace

ConfigResult check_fixed_point_scene(const OscillatorParams& p, const DiscreteModel& model,
                                     int integer_bits, int fraction_bits, int tick_level,
                                     ParameterUnits units) noexcept {
  ConfigResult r;
  char format[16] = "Q";
  format_name(integer_bits, fraction_bits, format);
  Checker c{std::ldexp(1.0, integer_bits - kFixedPointHeadroomBits),
            kFixedPointMinimumSteps * std::ldexp(1.0, -fraction_bits), format, units, r};
  // Each check stops at the first failure; r then holds the verdict and its message.
  (void)(offered(p, c) && coefficients_fit(p, model, tick_level, c) &&
         intermediates_fit(p, model, c));
  return r;
}

}  // namespace stickslip
