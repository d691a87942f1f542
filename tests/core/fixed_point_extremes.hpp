// The Foundation issue's extremes for the fixed-point formats (test_fixed_point.cpp, Q23.40;
// test_fixed_point32.cpp, Q7.24 in scene units): the grid of scenes, and the tally of what each
// format did with them (refused by name, or run without saturation and bounded).
#pragma once

#include <cmath>
#include <cstring>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"

namespace stickslip::test {

// A refusal must start with one of these, then ':'.
inline bool names_a_fixed_point_parameter(const char* message) {
  static const char* const kParameters[] = {"mass_kg",
                                            "stiffness_n_per_m",
                                            "damping_ns_per_m",
                                            "kinetic_friction_n",
                                            "static_friction_n",
                                            "smoothing_constant_s_per_m",
                                            "dt_s",
                                            "model",
                                            "input_range_m_per_s2",
                                            "displacement_range_m",
                                            "integrator",
                                            "smoothing"};
  for (const char* name : kParameters) {
    const std::size_t n = std::strlen(name);
    if (std::strncmp(message, name, n) == 0 && message[n] == ':') return true;
  }
  return false;
}

struct ExtremeTally {
  int accepted = 0, refused = 0, failures = 0;
  SimpleString listed;
  void fail(const SimpleString& what) {
    if (failures++ < 10) listed += SimpleString("\n\t  ") + what;
  }
};

inline SimpleString describe_scene(const OscillatorParams& p) {
  return StringFromFormat("%s/%s c=%g %s F_fk=%g b=%g dt=%g", model_name(p.model),
                          smoothing_name(p.smoothing), p.smoothing_constant_s_per_m,
                          integrator_name(p.integrator), p.kinetic_friction_n, p.damping_ns_per_m,
                          p.dt_s);
}

// One scene of the grid: refused by name, or run with no saturation, |x_r| <= bound_m and the
// stuck fraction in [0, 1]. `seat` is configured here; model(seat) is its Oscillator (for reset
// and the saturation count), input(seat, a_u) and metres(seat, x_r) the format's conversions.
template <typename Seat, typename Model, typename Input, typename Metres>
void run_extreme(Seat& seat, const OscillatorParams& p, const std::vector<double>& a_u,
                 double bound_m, ExtremeTally& tally, Model model, Input input, Metres metres) {
  const ConfigResult result = seat.configure(p);
  const SimpleString what = describe_scene(p);
  if (!result.ok()) {
    ++tally.refused;
    if (!names_a_fixed_point_parameter(result.message.c_str()))
      tally.fail(what + ": refusal names no parameter: " + result.message.c_str());
    return;
  }
  ++tally.accepted;
  using Scalar = typename Seat::Scalar;
  model(seat).reset(Scalar(0), Scalar(0), input(seat, a_u[0]));
  bool bounded = true;
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const auto out = seat.step(input(seat, a_u[n]));
    if (!(std::fabs(metres(seat, out.x_r_m)) <= bound_m)) bounded = false;
    const double stuck = out.stuck_fraction.to_double();
    if (stuck < 0.0 || stuck > 1.0) bounded = false;
  }
  if (model(seat).saturated_steps() != 0) tally.fail(what + ": saturated");
  if (!bounded) tally.fail(what + ": |x_r| beyond its bound or stuck fraction outside [0, 1]");
}

template <typename Law>
struct LawTag {
  using type = Law;
};

// The grid (K 0..100, damping ratio 0..2, c up to 1e6, dt 1e-5..0.05, every law and integrator
// fixed point offers) with the given ranges: visit(params, a_u, LawTag<Law>{}) for each scene.
template <typename Visit>
void for_each_extreme_scene(double input_range_m_per_s2, double displacement_range_m,
                            Visit&& visit) {
  const auto signal = make_lorry_signal(7, 0.35);
  const double critical = 2.0 * std::sqrt(kStiffnessNPerM * kMassKg);
  for (double dt : {1e-5, 1e-4, 1e-3, 1e-2, 0.05}) {
    const std::vector<double> a_u = signal.sample(dt, 600);
    for (double k_factor : {0.0, 0.5, 3.0, 100.0}) {
      for (double zeta : {0.0, 0.25, 2.0}) {
        for (Integrator integrator :
             {Integrator::euler, Integrator::symplectic, Integrator::exact}) {
          OscillatorParams p =
              reference_params(FrictionModel::linear, integrator, dt, zeta * critical);
          p.input_range_m_per_s2 = input_range_m_per_s2;
          p.displacement_range_m = displacement_range_m;
          p.kinetic_friction_n = kinetic_friction_for_den_hartog(k_factor, kMassKg, 0.35);
          p.static_friction_n = 1.25 * p.kinetic_friction_n;
          visit(p, a_u, LawTag<NoFriction>{});
          p.model = FrictionModel::signum;
          visit(p, a_u, LawTag<SignumFriction>{});
          p.model = FrictionModel::stick_slip;
          visit(p, a_u, LawTag<CoulombStickSlip>{});
          p.model = FrictionModel::smooth;
          p.smoothing = SmoothingLaw::rational;
          for (double c : {1.0, 1e3, 1e6}) {
            p.smoothing_constant_s_per_m = c;
            visit(p, a_u, LawTag<SmoothFriction<SmoothingLaw::rational>>{});
          }
        }
      }
    }
  }
}

}  // namespace stickslip::test
