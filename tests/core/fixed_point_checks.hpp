// The checks both fixed-point formats must pass, written once and instantiated for each
// (test_fixed_point.cpp: Q23.40 `Fixed` on the SI scene; test_fixed_point32.cpp: Q7.24 `Fixed32`
// in scene units), so that the two formats are held to the same bar: the rounded product, the
// oscillator against double, refusals that name the parameter, and the extreme scenes (refused by
// name, or run without saturation and bounded).
//
// A format is described by an adapter:
//   struct Format {
//     using Scalar = ...;
//     template <typename Law> using Seat = ...;  // configure(params), step(Scalar a_u)
//     static constexpr const char* kName = ...;  // in the labels of the noted margins
//     static OscillatorParams params(FrictionModel, Integrator);  // the scene it is tested on
//     template <typename S> static auto& model(S& seat);  // its Oscillator: reset, saturation
//     template <typename S> static Scalar input(S& seat, double a_m_per_s2);  // SI -> format
//     template <typename S> static double metres(S& seat, Scalar x_r);        // format -> SI
//     template <typename S> static double acceleration(S& seat, Scalar a_x);  // format -> SI
//   };
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "exact_rounding.hpp"
#include "oracles.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip::test {

inline bool contains(const char* text, const char* part) {
  return std::strstr(text, part) != nullptr;
}
inline bool starts_with(const char* text, const char* prefix) {
  return std::strncmp(text, prefix, std::strlen(prefix)) == 0;
}

// A refusal: not ok, the message starts with "<parameter>:" and names the quantity that would
// not fit.
inline void check_refused_naming(const ConfigResult& result, const char* parameter,
                                 const char* quantity) {
  CHECK_FALSE_TEXT(result.ok(), parameter);
  CHECK_TEXT(starts_with(result.message.c_str(), parameter), result.message.c_str());
  CHECK_TEXT(contains(result.message.c_str(), quantity), result.message.c_str());
}

struct FixedVsDouble {
  double transmissibility_fixed, transmissibility_double;
  double stick_fixed, stick_double;
  double max_x_error_m;
  std::uint64_t saturated_steps;
};

// The format's seat and a double oscillator on the same a_u (SI), from rest: their figures, the
// largest |x_r| difference in metres, and the fixed run's saturated steps.
template <typename Format, typename Law>
FixedVsDouble compare_with_double(const OscillatorParams& params, const std::vector<double>& a_u) {
  using Scalar = typename Format::Scalar;
  typename Format::template Seat<Law> fixed;
  Oscillator<double, Law> reference;
  const ConfigResult fixed_status = fixed.configure(params);
  CHECK_TEXT(fixed_status.ok(), fixed_status.message.c_str());
  CHECK(reference.configure(params).ok());
  Format::model(fixed).reset(Scalar(0), Scalar(0), Format::input(fixed, a_u[0]));
  reference.reset(0.0, 0.0, a_u[0]);
  RunningStatistics<double> fixed_stats, double_stats;
  fixed_stats.reset();
  double_stats.reset();
  FixedVsDouble c{};
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const auto f = fixed.step(Format::input(fixed, a_u[n]));
    const auto d = reference.step(a_u[n]);
    fixed_stats.add_sample(a_u[n], Format::acceleration(fixed, f.a_x_m_per_s2));
    fixed_stats.add_step(f.stuck_fraction.to_double());
    double_stats.add_sample(a_u[n], d.a_x_m_per_s2);
    double_stats.add_step(d.stuck_fraction);
    const double error = std::fabs(Format::metres(fixed, f.x_r_m) - d.x_r_m);
    if (error > c.max_x_error_m) c.max_x_error_m = error;
  }
  c.transmissibility_fixed = fixed_stats.transmissibility();
  c.transmissibility_double = double_stats.transmissibility();
  c.stick_fixed = fixed_stats.stick_probability();
  c.stick_double = double_stats.stick_probability();
  c.saturated_steps = Format::model(fixed).saturated_steps();
  return c;
}

inline std::string margin_label(const char* format_name, const char* what) {
  return std::string(format_name) + " " + what;
}

// 30 s of the lorry-like scene at dt = 1 ms, K = 1.3, exact and symplectic: the targets (T_ax
// within 1 %, p within 0.01, no saturation) noted as margins and asserted ten times tighter.
template <typename Format>
void check_stick_slip_agrees_with_double_on_the_lorry_scene() {
  const auto a_u = make_lorry_signal(3, 0.35).sample(1e-3, 30001);
  for (Integrator integrator : {Integrator::exact, Integrator::symplectic}) {
    OscillatorParams p = Format::params(FrictionModel::stick_slip, integrator);
    p.kinetic_friction_n = kinetic_friction_for_den_hartog(1.3, kMassKg, 0.35);
    p.static_friction_n = 1.25 * p.kinetic_friction_n;
    const FixedVsDouble c = compare_with_double<Format, CoulombStickSlip>(p, a_u);
    const double t_error = std::fabs(c.transmissibility_fixed / c.transmissibility_double - 1.0);
    const double p_error = std::fabs(c.stick_fixed - c.stick_double);
    note_margin(margin_label(Format::kName, "vs double T_ax relative error").c_str(), t_error,
                0.01);
    note_margin(margin_label(Format::kName, "vs double p absolute error").c_str(), p_error, 0.01);
    CHECK(t_error < 1e-3);
    CHECK(p_error < 1e-3);
    CHECK(c.stick_double > 0.3);  // the scene does stick
    CHECK(c.max_x_error_m < 1e-4);
    LONGS_EQUAL(0, c.saturated_steps);
  }
}

// The laws that hold no stick state (signum, rational smoothing with the given constant) against
// double: T_ax within 0.1 %, the smooth law's x_r within max_x_error_m, no saturation. The
// constant and the bound are the format's: c v_r must fit its range.
template <typename Format>
void check_held_laws_agree_with_double(double smoothing_constant_s_per_m, double max_x_error_m) {
  const auto a_u = make_lorry_signal(4, 0.35).sample(1e-3, 10001);
  OscillatorParams p = Format::params(FrictionModel::signum, Integrator::exact);
  p.kinetic_friction_n = 20.0;
  FixedVsDouble c = compare_with_double<Format, SignumFriction>(p, a_u);
  CHECK(std::fabs(c.transmissibility_fixed / c.transmissibility_double - 1.0) < 1e-3);
  LONGS_EQUAL(0, c.saturated_steps);
  p.model = FrictionModel::smooth;
  p.smoothing = SmoothingLaw::rational;
  p.smoothing_constant_s_per_m = smoothing_constant_s_per_m;
  c = compare_with_double<Format, SmoothFriction<SmoothingLaw::rational>>(p, a_u);
  CHECK(std::fabs(c.transmissibility_fixed / c.transmissibility_double - 1.0) < 1e-3);
  CHECK(c.max_x_error_m < max_x_error_m);
  LONGS_EQUAL(0, c.saturated_steps);
}

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

// One scene of the grid: refused by name, or run with no saturation, |x_r| within the declared
// stroke and the stuck fraction in [0, 1]. `seat` is configured here.
template <typename Format, typename Seat>
void run_extreme(Seat& seat, const OscillatorParams& p, const std::vector<double>& a_u,
                 ExtremeTally& tally) {
  const ConfigResult result = seat.configure(p);
  const SimpleString what = describe_scene(p);
  if (!result.ok()) {
    ++tally.refused;
    if (!names_a_fixed_point_parameter(result.message.c_str()))
      tally.fail(what + ": refusal names no parameter: " + result.message.c_str());
    return;
  }
  ++tally.accepted;
  using Scalar = typename Format::Scalar;
  Format::model(seat).reset(Scalar(0), Scalar(0), Format::input(seat, a_u[0]));
  bool bounded = true;
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const auto out = seat.step(Format::input(seat, a_u[n]));
    if (!(std::fabs(Format::metres(seat, out.x_r_m)) <= p.displacement_range_m)) bounded = false;
    const double stuck = out.stuck_fraction.to_double();
    if (stuck < 0.0 || stuck > 1.0) bounded = false;
  }
  if (Format::model(seat).saturated_steps() != 0) tally.fail(what + ": saturated");
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

// The extremes of the grid with the given input range and a 1 m stroke: every scene refused by
// name or run without saturation and bounded; the grid must hold both kinds.
template <typename Format>
void check_extremes_are_refused_by_name_or_run_without_saturation(double input_range_m_per_s2) {
  ExtremeTally tally;
  for_each_extreme_scene(input_range_m_per_s2, 1.0,
                         [&](const OscillatorParams& p, const std::vector<double>& a_u, auto law) {
                           typename Format::template Seat<typename decltype(law)::type> seat;
                           run_extreme<Format>(seat, p, a_u, tally);
                         });
  CHECK_TEXT(tally.failures == 0,
             StringFromFormat("%d failing scenes:%s", tally.failures, tally.listed.asCharString())
                 .asCharString());
  CHECK(tally.accepted > 100);
  CHECK(tally.refused > 0);
  note_margin(margin_label(Format::kName, "grid scenes accepted").c_str(), tally.accepted, 0.0);
  note_margin(margin_label(Format::kName, "grid scenes refused").c_str(), tally.refused, 0.0);
}

}  // namespace stickslip::test
