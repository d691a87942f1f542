// Extreme scenes: every configuration is either refused by configure() with a message that names
// the parameter, or runs without ever producing NaN/Inf, without exhausting the event budget and
// without the non-finite guard having to restart the state.
#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/models/dispatch.hpp"

using namespace stickslip;

namespace {

constexpr double kLorryRms = 0.35;  // m/s^2
// The lorry-like input peaks near 1.2 m/s^2; a stable passive seat answers it with centimetres
// (m a/|k - m w^2| summed over its lines, < 0.1 m even undamped). An exploding scheme passes any
// bound on the way to Inf, so bounding x_r catches in a short run what Inf shows in a long one.
constexpr double kTravelBound = 1.0;  // m

const char* const kParameterNames[] = {"mass_kg",
                                       "stiffness_n_per_m",
                                       "damping_ns_per_m",
                                       "kinetic_friction_n",
                                       "static_friction_n",
                                       "stribeck_velocity_m_per_s",
                                       "smoothing_constant_s_per_m",
                                       "dt_s",
                                       "model"};

// The message starts with "<parameter>:" for one of the parameters of OscillatorParams.
bool names_a_parameter(const char* message) {
  for (const char* name : kParameterNames) {
    const std::size_t n = std::strlen(name);
    if (std::strncmp(message, name, n) == 0 && message[n] == ':') return true;
  }
  return false;
}

bool starts_with(const char* text, const char* prefix) {
  return std::strncmp(text, prefix, std::strlen(prefix)) == 0;
}

struct LawCase {
  FrictionModel model;
  SmoothingLaw smoothing;
  double smoothing_c;
};

std::vector<LawCase> all_law_cases() {
  std::vector<LawCase> laws = {{FrictionModel::linear, SmoothingLaw::tanh, 1000.0},
                               {FrictionModel::signum, SmoothingLaw::tanh, 1000.0},
                               {FrictionModel::stick_slip, SmoothingLaw::tanh, 1000.0},
                               {FrictionModel::stribeck, SmoothingLaw::tanh, 1000.0}};
  for (SmoothingLaw s :
       {SmoothingLaw::atan, SmoothingLaw::tanh, SmoothingLaw::erf, SmoothingLaw::rational}) {
    for (double c : {1.0, 1e3, 1e6}) laws.push_back({FrictionModel::smooth, s, c});
  }
  return laws;
}

const Integrator kAllIntegrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                      Integrator::exact};

struct RunVerdict {
  bool configured = false;
  Status status = Status::ok;
  bool message_names_parameter = true;
  bool message_names_limit = true;
  bool all_finite = true;
  bool bounded = true;  // |x_r| <= kTravelBound throughout
  bool stuck_time_in_range = true;
  std::uint64_t budget_exhausted = 0;
  std::uint64_t state_resets = 0;
  int fp_flags = 0;
};

template <typename T>
bool finite_output(const StepOutput<T>& out) {
  return std::isfinite(out.x_r_m) && std::isfinite(out.v_r_m_per_s) &&
         std::isfinite(out.a_x_m_per_s2) && std::isfinite(out.friction_n) &&
         std::isfinite(out.stuck_time_s) && std::isfinite(out.stuck_fraction);
}

// Configures and, if accepted, runs the samples from rest, checking every output.
template <typename T>
RunVerdict run_scene(const OscillatorParams& params, const std::vector<double>& input,
                     std::size_t steps, std::size_t ratio = 1) {
  std::feclearexcept(FE_ALL_EXCEPT);
  RunVerdict verdict = with_oscillator<T>(params, [&](auto& seat) {
    RunVerdict v;
    const auto config = seat.configure(params);
    v.status = config.status;
    if (!config.ok()) {
      v.message_names_parameter = names_a_parameter(config.message.c_str());
      if (config.status == Status::unstable)
        v.message_names_limit = std::strstr(config.message.c_str(), "stab") != nullptr;
      return v;
    }
    v.configured = true;
    seat.reset(T(0), T(0), static_cast<T>(input[0]));
    const T dt = seat.dt_s();
    for (std::size_t j = 1; j <= steps; ++j) {
      const auto out = seat.step(static_cast<T>(test::refine_linear(input, j, ratio)));
      if (!finite_output(out)) v.all_finite = false;
      if (!(std::fabs(static_cast<double>(out.x_r_m)) <= kTravelBound)) v.bounded = false;
      if (!(out.stuck_time_s >= T(0) && out.stuck_time_s <= dt && out.stuck_fraction >= T(0) &&
            out.stuck_fraction <= T(1)))
        v.stuck_time_in_range = false;
    }
    v.budget_exhausted = seat.event_budget_exhausted();
    v.state_resets = seat.state_resets();
    return v;
  });
  verdict.fp_flags = std::fetestexcept(FE_DIVBYZERO | FE_OVERFLOW | FE_UNDERFLOW | FE_INVALID);
  std::feclearexcept(FE_ALL_EXCEPT);  // reported below with the scene that raised it
  return verdict;
}

SimpleString describe(const char* type, const OscillatorParams& p) {
  return StringFromFormat("%s %s/%s c=%g %s F_fk=%g N b=%g N s/m dt=%g s", type,
                          model_name(p.model), smoothing_name(p.smoothing),
                          p.smoothing_constant_s_per_m, integrator_name(p.integrator),
                          p.kinetic_friction_n, p.damping_ns_per_m, p.dt_s);
}

SimpleString describe_flags(int flags) {
  return StringFromFormat("%s%s%s%s", (flags & FE_DIVBYZERO) ? "divbyzero " : "",
                          (flags & FE_OVERFLOW) ? "overflow " : "",
                          (flags & FE_UNDERFLOW) ? "underflow " : "",
                          (flags & FE_INVALID) ? "invalid " : "");
}

struct GridTally {
  int accepted = 0, refused = 0, failures = 0;
  SimpleString listed;  // the first few failing scenes, one per line
  void fail(const SimpleString& what) {
    if (failures++ < 20) listed += SimpleString("\n\t  ") + what;
  }
};

template <typename T>
void sweep_grid(const char* type, std::size_t steps, GridTally& tally) {
  const double den_hartog_k[] = {0.0, 0.1, 0.5, 1.0, 3.0, 10.0, 30.0, 100.0};
  const double damping_ratio[] = {0.0, 0.25, 1.0, 2.0};
  const double steps_s[] = {1e-5, 1e-4, 1e-3, 1e-2, 0.05};
  const auto laws = all_law_cases();
  const auto signal = test::make_lorry_signal(7, kLorryRms);
  const double critical = 2.0 * std::sqrt(test::kStiffnessNPerM * test::kMassKg);
  for (double dt : steps_s) {
    const auto input = signal.sample(dt, steps + 1);
    for (double k_factor : den_hartog_k) {
      for (double zeta : damping_ratio) {
        for (const LawCase& law : laws) {
          for (Integrator integrator : kAllIntegrators) {
            OscillatorParams p = test::reference_params(law.model, integrator, dt, zeta * critical);
            p.kinetic_friction_n =
                test::kinetic_friction_for_den_hartog(k_factor, test::kMassKg, kLorryRms);
            p.static_friction_n = 1.25 * p.kinetic_friction_n;
            p.smoothing = law.smoothing;
            p.smoothing_constant_s_per_m = law.smoothing_c;
            p.stribeck_velocity_m_per_s = 0.01;
            const RunVerdict v = run_scene<T>(p, input, steps);
            const SimpleString what = describe(type, p);
            if (!v.configured) {
              ++tally.refused;
              if (!v.message_names_parameter) tally.fail(what + ": refusal names no parameter");
              if (!v.message_names_limit) tally.fail(what + ": unstable but names no limit");
              // The exact integrator has no stability limit: it must take every scene here.
              if (integrator == Integrator::exact) tally.fail(what + ": exact integrator refused");
            } else {
              ++tally.accepted;
              if (!v.all_finite) tally.fail(what + ": non-finite output");
              if (!v.bounded) tally.fail(what + ": |x_r| beyond 1 m (unstable)");
              if (!v.stuck_time_in_range) tally.fail(what + ": stuck time outside [0, dt]");
              if (v.budget_exhausted != 0) tally.fail(what + ": event budget exhausted");
              if (v.state_resets != 0) tally.fail(what + ": state reset by the guard");
            }
            if (v.fp_flags != 0) tally.fail(what + ": raised " + describe_flags(v.fp_flags));
          }
        }
      }
    }
  }
}

}  // namespace

TEST_GROUP(Extremes){};

// K 0..100, damping ratio 0..2, smoothing c up to 1e6, dt 1e-5..0.05, every law and integrator,
// double and float: refused by name, or finite throughout with no event-budget or guard hit and
// no floating-point exception.
TEST(Extremes, EverySceneIsRefusedByNameOrRunsFinite) {
  GridTally tally;
  sweep_grid<double>("double", 3000, tally);
  sweep_grid<float>("float", 1000, tally);
  CHECK_TEXT(tally.failures == 0, StringFromFormat("%d failing scenes, the first ones:%s",
                                                   tally.failures, tally.listed.asCharString())
                                      .asCharString());
  CHECK(tally.accepted > 1000);
  CHECK(tally.refused > 0);
  test::note_margin("grid scenes accepted", tally.accepted, 0.0);
  test::note_margin("grid scenes refused", tally.refused, 0.0);
}

// 1e7-step runs (100 s at dt = 1e-5 s) of the input-heavy scenes: no drift into NaN/Inf, no
// budget or guard hits, in double and float.
TEST(Extremes, TenMillionStepRunsStayFinite) {
  const auto signal = test::make_lorry_signal(99, kLorryRms);
  const auto coarse = signal.sample(1e-3, 100001);  // refined 100 times: 1e7 steps
  struct LongScene {
    FrictionModel model;
    Integrator integrator;
    double k_factor;
    bool in_float;
  };
  const LongScene scenes[] = {
      {FrictionModel::stick_slip, Integrator::exact, 1.0, false},
      {FrictionModel::stick_slip, Integrator::exact, 1.0, true},
      {FrictionModel::stribeck, Integrator::rk4, 3.0, false},
      {FrictionModel::smooth, Integrator::exact, 0.5, true},
  };
  for (const LongScene& s : scenes) {
    OscillatorParams p = test::reference_params(s.model, s.integrator, 1e-5);
    p.kinetic_friction_n =
        test::kinetic_friction_for_den_hartog(s.k_factor, test::kMassKg, kLorryRms);
    p.static_friction_n = 1.25 * p.kinetic_friction_n;
    p.smoothing_constant_s_per_m = 1e6;
    const RunVerdict v = s.in_float ? run_scene<float>(p, coarse, 10000000, 100)
                                    : run_scene<double>(p, coarse, 10000000, 100);
    const SimpleString what = describe(s.in_float ? "float" : "double", p);
    CHECK_TEXT(v.configured, what.asCharString());
    CHECK_TEXT(v.all_finite, what.asCharString());
    CHECK_TEXT(v.bounded, what.asCharString());
    CHECK_TEXT(v.stuck_time_in_range, what.asCharString());
    CHECK_TEXT(v.budget_exhausted == 0, what.asCharString());
    CHECK_TEXT(v.state_resets == 0, what.asCharString());
    CHECK_TEXT(v.fp_flags == 0, (what + ": raised " + describe_flags(v.fp_flags)).asCharString());
  }
}

// Beyond an explicit scheme's stability limit the scene is refused with status unstable, and the
// message names the parameter and the limit.
TEST(Extremes, ExplicitSchemeBeyondStabilityLimitIsRefusedNamingTheLimit) {
  struct Case {
    FrictionModel model;
    Integrator integrator;
    double damping, c, dt;
    const char* parameter;
  };
  const Case cases[] = {
      // c F_fk dt/m = 452: the smoothed law is a stiff damper for the explicit schemes.
      {FrictionModel::smooth, Integrator::euler, test::kDampingNsPerM, 1e6, 1e-3,
       "smoothing_constant_s_per_m:"},
      {FrictionModel::smooth, Integrator::symplectic, test::kDampingNsPerM, 1e6, 1e-3,
       "smoothing_constant_s_per_m:"},
      {FrictionModel::smooth, Integrator::rk4, test::kDampingNsPerM, 1e6, 1e-3,
       "smoothing_constant_s_per_m:"},
      // Euler beyond b/k = 43.8 ms for the damped seat.
      {FrictionModel::linear, Integrator::euler, test::kDampingNsPerM, 1e3, 0.05, "dt_s:"},
      // Symplectic beyond omega0 dt = 2, RK4 beyond omega0 dt = 2.83 (linear: no event limit).
      {FrictionModel::linear, Integrator::symplectic, 0.0, 1e3, 0.2, "dt_s:"},
      {FrictionModel::linear, Integrator::rk4, 0.0, 1e3, 0.3, "dt_s:"},
  };
  for (const Case& c : cases) {
    OscillatorParams p = test::reference_params(c.model, c.integrator, c.dt, c.damping);
    p.kinetic_friction_n = 40.0;
    p.smoothing_constant_s_per_m = c.c;
    const RunVerdict v = run_scene<double>(p, {0.0, 0.0}, 1);
    const SimpleString what = describe("double", p);
    CHECK_TEXT(!v.configured, what.asCharString());
    CHECK_TEXT(v.status == Status::unstable, what.asCharString());
    with_oscillator<double>(p, [&](auto& seat) {
      const auto config = seat.configure(p);
      CHECK_TEXT(starts_with(config.message.c_str(), c.parameter), config.message.c_str());
      STRCMP_CONTAINS("stability limit is dt < ", config.message.c_str());
      return 0;
    });
  }
  // The limit quoted for the smoothed Euler case is the real one: 2 m/(c F_fk) = 4.42e-6 s.
  OscillatorParams p = test::reference_params(FrictionModel::smooth, Integrator::euler, 4.3e-6);
  p.kinetic_friction_n = 40.0;
  p.smoothing_constant_s_per_m = 1e6;
  Oscillator<double, SmoothFriction<SmoothingLaw::tanh>> seat;
  CHECK_TEXT(seat.configure(p).ok(), "just inside the limit");
  p.dt_s = 4.5e-6;
  CHECK_FALSE(seat.configure(p).ok());
}

// Explicit Euler on an undamped seat has spectral radius sqrt(1 + (omega0 dt)^2) > 1 for every
// dt > 0: no step is stable, so it must be refused at every dt. A smoothed friction law does not
// change that: its slope c F_fk s'(0) damps only around v_r = 0 and saturates at F_fk, so at larger
// amplitudes the scheme is undamped Euler again (Passivity.ExplicitEulerIsBoundedWheneverAccepted
// shows the growth).
template <typename Check>
void for_each_undamped_euler_scene(Check check) {
  for (double dt : {0.05, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7}) {
    for (FrictionModel model : {FrictionModel::linear, FrictionModel::signum, FrictionModel::smooth,
                                FrictionModel::stick_slip, FrictionModel::stribeck}) {
      OscillatorParams p = test::reference_params(model, Integrator::euler, dt, 0.0);
      p.kinetic_friction_n = 40.0;
      p.static_friction_n = 50.0;
      p.smoothing_constant_s_per_m = 1000.0;
      with_oscillator<double>(p, [&](auto& seat) {
        check(p, seat.configure(p));
        return 0;
      });
    }
  }
}

TEST(Extremes, EulerWithoutDampingIsRefusedAtEveryStep) {
  SimpleString failures;
  int failed = 0;
  for_each_undamped_euler_scene([&](const OscillatorParams& p, const ConfigResult& config) {
    const bool ok = !config.ok() && config.status == Status::unstable &&
                    names_a_parameter(config.message.c_str());
    if (!ok && failed++ < 12)
      failures += SimpleString("\n\t  ") + describe("double", p) + ": accepted";
  });
  CHECK_TEXT(failed == 0, StringFromFormat("%d undamped Euler scenes accepted:%s", failed,
                                           failures.asCharString())
                              .asCharString());
}

// Where it is refused, the message must not quote a stability limit "dt < ...": there is none.
TEST(Extremes, EulerWithoutDampingRefusalQuotesNoStabilityLimit) {
  SimpleString failures;
  int failed = 0;
  for_each_undamped_euler_scene([&](const OscillatorParams& p, const ConfigResult& config) {
    if (config.ok()) return;  // EulerWithoutDampingIsRefusedAtEveryStep reports those
    if (std::strstr(config.message.c_str(), "limit is dt <") != nullptr && failed++ < 3)
      failures += SimpleString("\n\t  ") + describe("double", p) + ": " + config.message.c_str();
  });
  CHECK_TEXT(failed == 0, StringFromFormat("%d refusals quote a stability limit, e.g.:%s", failed,
                                           failures.asCharString())
                              .asCharString());
}

// Bad parameters: refused with the right status and a message starting with the parameter name.
TEST(Extremes, BadParametersAreRefusedNamingTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* parameter;
    Status status;
    FrictionModel model;
    void (*mutate)(OscillatorParams&, double nan, double inf);
  };
  const Case cases[] = {
      {"mass_kg:", Status::not_finite, FrictionModel::stick_slip,
       [](OscillatorParams& p, double n, double) { p.mass_kg = n; }},
      {"mass_kg:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.mass_kg = -88.4; }},
      {"mass_kg:", Status::out_of_range, FrictionModel::linear,
       [](OscillatorParams& p, double, double) { p.mass_kg = 0.0; }},
      {"stiffness_n_per_m:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.stiffness_n_per_m = 0.0; }},
      {"stiffness_n_per_m:", Status::not_finite, FrictionModel::linear,
       [](OscillatorParams& p, double, double i) { p.stiffness_n_per_m = i; }},
      {"damping_ns_per_m:", Status::out_of_range, FrictionModel::signum,
       [](OscillatorParams& p, double, double) { p.damping_ns_per_m = -1.0; }},
      {"damping_ns_per_m:", Status::not_finite, FrictionModel::signum,
       [](OscillatorParams& p, double n, double) { p.damping_ns_per_m = n; }},
      {"kinetic_friction_n:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.kinetic_friction_n = -5.0; }},
      {"kinetic_friction_n:", Status::not_finite, FrictionModel::smooth,
       [](OscillatorParams& p, double n, double) { p.kinetic_friction_n = n; }},
      {"static_friction_n:", Status::static_below_kinetic, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) {
         p.kinetic_friction_n = 40.0;
         p.static_friction_n = 39.9;
       }},
      {"static_friction_n:", Status::static_below_kinetic, FrictionModel::stribeck,
       [](OscillatorParams& p, double, double) {
         p.kinetic_friction_n = 40.0;
         p.static_friction_n = 0.0;
       }},
      {"static_friction_n:", Status::not_finite, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double i) { p.static_friction_n = -i; }},
      {"stribeck_velocity_m_per_s:", Status::out_of_range, FrictionModel::stribeck,
       [](OscillatorParams& p, double, double) { p.stribeck_velocity_m_per_s = 0.0; }},
      {"smoothing_constant_s_per_m:", Status::out_of_range, FrictionModel::smooth,
       [](OscillatorParams& p, double, double) { p.smoothing_constant_s_per_m = 0.0; }},
      {"smoothing_constant_s_per_m:", Status::not_finite, FrictionModel::smooth,
       [](OscillatorParams& p, double n, double) { p.smoothing_constant_s_per_m = n; }},
      {"dt_s:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.dt_s = 0.0; }},
      {"dt_s:", Status::out_of_range, FrictionModel::linear,
       [](OscillatorParams& p, double, double) { p.dt_s = -1e-3; }},
      {"dt_s:", Status::not_finite, FrictionModel::stick_slip,
       [](OscillatorParams& p, double n, double) { p.dt_s = n; }},
      // Denormal or tiny values reached the float step as 0 or infinity (found by fuzzing).
      {"dt_s:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.dt_s = 3.4e-315; }},
      {"stribeck_velocity_m_per_s:", Status::out_of_range, FrictionModel::stribeck,
       [](OscillatorParams& p, double, double) { p.stribeck_velocity_m_per_s = 1e-300; }},
      {"mass_kg:", Status::out_of_range, FrictionModel::linear,
       [](OscillatorParams& p, double, double) { p.mass_kg = 1e-300; }},
      {"stiffness_n_per_m:", Status::out_of_range, FrictionModel::signum,
       [](OscillatorParams& p, double, double) { p.stiffness_n_per_m = 1e-12; }},
      // The in-step event search needs omega0 dt <= pi/2 (dt <= 0.138 s here).
      {"dt_s:", Status::out_of_range, FrictionModel::stick_slip,
       [](OscillatorParams& p, double, double) { p.dt_s = 0.2; }},
  };
  for (const Case& c : cases) {
    OscillatorParams p = test::reference_params(c.model, Integrator::exact, 1e-3);
    p.kinetic_friction_n = 40.0;
    p.static_friction_n = 50.0;
    c.mutate(p, nan, inf);
    with_oscillator<double>(p, [&](auto& seat) {
      const auto config = seat.configure(p);
      CHECK_TEXT(!config.ok(), c.parameter);
      CHECK_TEXT(config.status == c.status,
                 StringFromFormat("%s got status %s: %s", c.parameter, status_name(config.status),
                                  config.message.c_str())
                     .asCharString());
      CHECK_TEXT(starts_with(config.message.c_str(), c.parameter), config.message.c_str());
      return 0;
    });
    // The float oscillator validates the same way.
    with_oscillator<float>(p, [&](auto& seat) {
      CHECK_TEXT(seat.configure(p).status == c.status, c.parameter);
      return 0;
    });
  }
  // A law instantiated for another model refuses by naming "model".
  Oscillator<double, CoulombStickSlip> seat;
  const auto config =
      seat.configure(test::reference_params(FrictionModel::linear, Integrator::exact, 1e-3));
  CHECK(config.status == Status::unsupported);
  CHECK_TEXT(starts_with(config.message.c_str(), "model:"), config.message.c_str());
}

// A non-finite input sample is replaced by the previous one and counted; the state stays finite
// and identical to a run that was fed the previous sample instead.
template <typename T>
void check_non_finite_input_is_replaced(FrictionModel model) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, 1e-3);
  p.kinetic_friction_n = 35.0;
  p.static_friction_n = 45.0;
  const T bad[] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity(),
                   -std::numeric_limits<T>::infinity()};
  with_oscillator<T>(p, [&](auto& seat) {
    auto twin = seat;  // same law; fed the held sample instead of the bad one
    CHECK(seat.configure(p).ok());
    CHECK(twin.configure(p).ok());
    const auto signal = test::make_lorry_signal(5, 1.5);
    seat.reset(T(0), T(0), T(0));
    twin.reset(T(0), T(0), T(0));
    T previous = T(0);
    for (int n = 1; n <= 3000; ++n) {
      T a = static_cast<T>(signal.at(n * 1e-3));
      const bool inject = n % 100 == 0;
      const auto out = seat.step(inject ? bad[(n / 100) % 3] : a);
      const auto expected = twin.step(inject ? previous : a);
      CHECK(finite_output(out));
      CHECK(out.x_r_m == expected.x_r_m);
      CHECK(out.v_r_m_per_s == expected.v_r_m_per_s);
      CHECK(out.a_x_m_per_s2 == expected.a_x_m_per_s2);
      if (!inject) previous = a;
    }
    UNSIGNED_LONGS_EQUAL(30, seat.rejected_inputs());
    UNSIGNED_LONGS_EQUAL(0, twin.rejected_inputs());
    UNSIGNED_LONGS_EQUAL(0, seat.state_resets());
    return 0;
  });
}

TEST(Extremes, NonFiniteInputIsReplacedByThePreviousSample) {
  for (FrictionModel model : {FrictionModel::linear, FrictionModel::signum, FrictionModel::smooth,
                              FrictionModel::stick_slip, FrictionModel::stribeck}) {
    check_non_finite_input_is_replaced<double>(model);
    check_non_finite_input_is_replaced<float>(model);
  }
}

// Symplectic with a sticking law needs damping ratio >= 0.25 (omega0 dt)^2: without damping the
// refusal says that no dt is stable (never a bound such as "use dt <= 0 s"), names damping and
// the limit.
TEST(Extremes, UndampedSymplecticStickingRefusalSaysNoDtIsStable) {
  for (FrictionModel model : {FrictionModel::stick_slip, FrictionModel::stribeck}) {
    for (double dt : {1e-5, 1e-3, 0.05}) {
      OscillatorParams p = test::reference_params(model, Integrator::symplectic, dt, 0.0);
      p.kinetic_friction_n = 40.0;
      p.static_friction_n = 50.0;
      with_oscillator<double>(p, [&](auto& seat) {
        const auto config = seat.configure(p);
        CHECK(config.status == Status::unstable);
        CHECK_TEXT(starts_with(config.message.c_str(), "damping_ns_per_m:"),
                   config.message.c_str());
        STRCMP_CONTAINS("no dt is stable", config.message.c_str());
        STRCMP_CONTAINS("stability limit", config.message.c_str());
        CHECK_TEXT(std::strstr(config.message.c_str(), "dt <= 0 s") == nullptr,
                   config.message.c_str());
        // The whole message fits the fixed-capacity StatusMessage (ends with its advice).
        STRCMP_CONTAINS("or exact/rk4", config.message.c_str());
        return 0;
      });
    }
  }
  // Lightly damped (ratio 0.05 < 0.25 (omega0 dt)^2 = 0.081 at 50 ms): the limit dt is quoted,
  // and that message fits too.
  OscillatorParams p =
      test::reference_params(FrictionModel::stick_slip, Integrator::symplectic, 0.05,
                             0.05 * 2.0 * std::sqrt(test::kStiffnessNPerM * test::kMassKg));
  p.kinetic_friction_n = p.static_friction_n = 40.0;
  Oscillator<double, CoulombStickSlip> seat;
  const auto config = seat.configure(p);
  CHECK(config.status == Status::unstable);
  STRCMP_CONTAINS("use dt <= 0.039", config.message.c_str());
  STRCMP_CONTAINS("or exact/rk4", config.message.c_str());
}

// The refusal of a subnormal value quotes it: a formatter that scales by 10^exponent would divide
// by 10^-324 = 0 there (UBSan: NaN converted to int).
TEST(Extremes, RefusalQuotesSubnormalValues) {
  OscillatorParams p =
      test::reference_params(FrictionModel::stick_slip, Integrator::exact, 4.9406564584124654e-324);
  Oscillator<double, CoulombStickSlip> seat;
  const auto config = seat.configure(p);
  CHECK(config.status == Status::out_of_range);
  STRCMP_CONTAINS("got 4.94066e-324", config.message.c_str());
  StatusMessage message;
  message.append(2.2250738585072014e-308 / 4.0).append(" ").append(-1e-310, 3);
  STRCMP_EQUAL("5.56268e-309 -1e-310", message.c_str());
}
