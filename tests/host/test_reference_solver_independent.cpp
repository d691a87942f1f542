// The reference solver against an independent method written here: Boost.Odeint's Dormand-Prince
// 5(4) with dense output (tolerances 1e-13 relative, 1e-15 absolute), restarted at every sample,
// events found by scanning the dense output and bisecting it on v_r = 0, break-away by bisection
// on |F_L| = F_fs - no closed form, no Newton, no shared code. Also against the core's exact
// integrator, and the solver's adaptive path (Stribeck, smooth) against its closed-form path where
// the laws coincide. Worst errors are printed with STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <boost/numeric/odeint.hpp>

#include "../core/oracles.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/oscillator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

namespace odeint = boost::numeric::odeint;
using State = std::array<double, 2>;

constexpr double kAgreement = 1e-9;

// Friction while moving in direction d (d = +-1; the sign of v_r for the smooth laws' purpose is
// v itself).
double slip_friction(const OscillatorParams& p, double v, double d) {
  const double fk = p.kinetic_friction_n;
  switch (p.model) {
    case FrictionModel::linear:
      return 0.0;
    case FrictionModel::signum:
    case FrictionModel::stick_slip:
      return fk * d;
    case FrictionModel::stribeck: {
      const double r = std::fabs(v) / p.stribeck_velocity_m_per_s;
      double shape = 0.0;  // exp(-r^2) without underflow (an if, not ?:, which may run both arms)
      if (r < 1e-100) {
        shape = 1.0;
      } else if (r <= 20.0) {
        shape = std::exp(-r * r);
      }
      return d * (fk + (p.static_friction_n - fk) * shape);
    }
    case FrictionModel::smooth:
      break;
  }
  const double cv = p.smoothing_constant_s_per_m * v;
  switch (p.smoothing) {
    case SmoothingLaw::atan:
      return fk * 2.0 / test::kPi * std::atan(cv);
    case SmoothingLaw::tanh:
      return fk * std::tanh(cv);
    case SmoothingLaw::erf:
      return fk * std::erf(cv);
    case SmoothingLaw::rational:
      break;
  }
  return fk * cv / (1.0 + std::fabs(cv));
}

// Integrates from (t0, from) to exactly t1 with error-controlled Dormand-Prince steps.
template <typename System>
void land(const System& system, const State& from, double t0, double t1, State& to) {
  to = from;
  if (t1 <= t0) return;
  odeint::integrate_adaptive(
      odeint::make_controlled(1e-17, 1e-14, odeint::runge_kutta_dopri5<State>()), system, to, t0,
      t1, (t1 - t0) / 2.0);
}

// Velocity over which the law's friction changes near v_r = 0 (0: a constant force).
double law_velocity_scale(const OscillatorParams& p) {
  if (p.model == FrictionModel::stribeck) return p.stribeck_velocity_m_per_s;
  if (p.model == FrictionModel::smooth) return 1.0 / p.smoothing_constant_s_per_m;
  return 0.0;
}
constexpr double kBandScales = 20.0;

struct Solution {
  std::vector<double> x, v, a_x;
  std::vector<std::uint8_t> stuck;
  double stuck_time_s = 0.0;
  std::uint64_t events = 0;
};

// Dormand-Prince with dense output, restarted at every sample (the FOH input has a kink there)
// and at every event. The dense output (4th order, not error-controlled) only locates instants;
// the state at an event or a sample end is integrated again from the start of its step, to land
// exactly there.
Solution dopri5_solution(const OscillatorParams& p, const std::vector<double>& a_u) {
  const bool sticking = p.model == FrictionModel::stick_slip || p.model == FrictionModel::stribeck;
  // c v/(1 + c|v|) has a jump in its second derivative at v_r = 0: steps end there instead.
  const bool kink = p.model == FrictionModel::smooth && p.smoothing == SmoothingLaw::rational;
  const double dt = p.dt_s, m = p.mass_kg, k = p.stiffness_n_per_m, b = p.damping_ns_per_m;
  const double fs = p.static_friction_n;
  Solution s;
  const std::size_t count = a_u.size();
  s.x.resize(count);
  s.v.resize(count);
  s.a_x.resize(count);
  s.stuck.resize(count);
  State y{0.0, 0.0};  // from rest: stuck unless the load exceeds F_fs
  const double limit0 = -m * a_u[0];
  double d = !sticking ? 1.0 : (std::fabs(limit0) <= fs ? 0.0 : (limit0 > 0.0 ? 1.0 : -1.0));
  const auto record = [&](std::size_t n) {
    s.x[n] = y[0];
    s.v[n] = y[1];
    s.stuck[n] = d == 0.0 ? 1 : 0;
    s.a_x[n] = d == 0.0 ? a_u[n] : -(k * y[0] + b * y[1] + slip_friction(p, y[1], d)) / m;
  };
  record(0);
  double h = dt / 8.0;
  for (std::size_t n = 1; n < count; ++n) {
    const double a0 = a_u[n - 1], a1 = a_u[n];
    const auto input = [&](double t) { return a0 + (a1 - a0) * (t / dt); };
    double t = 0.0;
    while (t < dt) {
      if (d == 0.0) {
        const auto limit = [&](double at) { return -(m * input(at) + k * y[0]); };
        const double limit_end = limit(dt);
        if (std::fabs(limit_end) <= fs) {
          s.stuck_time_s += dt - t;
          t = dt;
          break;
        }
        const double dir = limit_end > 0.0 ? 1.0 : -1.0;
        double lo = t, hi = dt;  // dir F_L - F_fs: <= 0 at lo, > 0 at hi
        for (int i = 0; i < 200 && hi - lo > 1e-16 * dt; ++i) {
          const double mid = 0.5 * (lo + hi);
          (dir * limit(mid) - fs > 0.0 ? hi : lo) = mid;
        }
        s.stuck_time_s += hi - t;
        t = hi;
        d = dir;
        y[1] = 0.0;
        ++s.events;
        continue;
      }
      const auto system = [&, d](const State& z, State& dz, double at) {
        dz[0] = z[1];
        dz[1] = -(k * z[0] + b * z[1] + slip_friction(p, z[1], d)) / m - input(at);
      };
      // The side v_r is on, or leaves 0 towards.
      State rate{};
      system(y, rate, t);
      const double dir =
          sticking ? d : (y[1] != 0.0 ? (y[1] > 0.0 ? 1.0 : -1.0) : (rate[1] < 0.0 ? -1.0 : 1.0));
      // Near v_r = 0 a Stribeck or smoothed law changes over a velocity of v_S or 1/c, within
      // microseconds; a step across that change sees it at too few stages for its error estimate
      // (or its dense output) to notice. Within kBandScales scales of 0 the steps are therefore
      // capped so that v_r changes by about a tenth of the scale per step (the cap follows
      // |dv_r/dt|); a step that reaches 0 from outside the band is redone in the band.
      const double scale = law_velocity_scale(p), band = kBandScales * scale;
      const auto acceleration = [&](const State& z, double at) {
        State derivative{};
        system(z, derivative, at);
        return std::max(std::fabs(derivative[1]), 1e-3);
      };
      const auto fine_step = [&](double accel) { return 0.1 * scale / accel; };
      auto normal = odeint::make_dense_output(1e-17, 1e-14, odeint::runge_kutta_dopri5<State>());
      auto fine = normal;
      double fine_cap = 0.0;
      const auto enter_band = [&](const State& z, double at) {
        fine_cap = fine_step(acceleration(z, at));
        fine =
            odeint::make_dense_output(1e-17, 1e-14, fine_cap, odeint::runge_kutta_dopri5<State>());
        fine.initialize(z, at, std::min(fine_cap, dt - at));
      };
      bool in_band = band > 0.0 && std::fabs(y[1]) < band;
      auto* stepper = &normal;
      if (in_band) {
        enter_band(y, t);
        stepper = &fine;
      } else {
        normal.initialize(y, t, std::min(h, dt - t));
      }
      const double restart = t;
      bool event = false, kinked = false;
      for (;;) {
        const auto [t0, t1] = stepper->do_step(system);
        h = stepper->current_time_step();
        const double end = std::min(t1, dt);
        // The first instant of the step with dir v_r <= 0 (the kink: < 0, once past the restart):
        // 16 points of the dense output, then bisection on it.
        double crossing = -1.0;
        if (sticking || kink) {
          double left = t0;
          for (int j = 1; j <= 16 && crossing < 0.0; ++j) {
            const double right = j == 16 ? end : t0 + (end - t0) * j / 16.0;
            State z{};
            stepper->calc_state(right, z);
            const bool crossed =
                kink ? dir * z[1] < 0.0 && right > restart + 1e-9 * dt : dir * z[1] <= 0.0;
            if (crossed) {
              double lo = left, hi = right;
              for (int i = 0; i < 200 && hi - lo > 1e-16 * dt; ++i) {
                const double mid = 0.5 * (lo + hi);
                stepper->calc_state(mid, z);
                (dir * z[1] > 0.0 ? lo : hi) = mid;
              }
              crossing = hi;
            }
            left = right;
          }
        }
        if (crossing >= 0.0 && !in_band && band > 0.0) {
          enter_band(normal.previous_state(), t0);
          stepper = &fine;
          in_band = true;
          continue;
        }
        if (crossing >= 0.0) {
          land(system, stepper->previous_state(), t0, crossing, y);
          y[1] = 0.0;
          t = crossing;
          (kink ? kinked : event) = true;
          break;
        }
        if (t1 >= dt) {
          land(system, stepper->previous_state(), t0, dt, y);
          t = dt;
          break;
        }
        const State now = stepper->current_state();
        if (in_band && std::fabs(now[1]) > band) {
          normal.initialize(now, t1, h);
          stepper = &normal;
          in_band = false;
        } else if (band > 0.0 && std::fabs(now[1]) < band) {
          const double wanted = fine_step(acceleration(now, t1));
          if (!in_band || wanted < 0.5 * fine_cap || wanted > 2.0 * fine_cap) {
            enter_band(now, t1);
            stepper = &fine;
            in_band = true;
          }
        }
      }
      if (event) {
        ++s.events;
        const double limit = -(m * input(t) + k * y[0]);
        d = std::fabs(limit) <= fs ? 0.0 : (limit > 0.0 ? 1.0 : -1.0);
      }
    }
    record(n);
  }
  return s;
}

struct Agreement {
  double x = 0.0, a_x = 0.0, p = 0.0;
  std::size_t stuck_mismatches = 0;
};

Agreement compare(const ReferenceTrace& r, const std::vector<double>& x,
                  const std::vector<double>& a_x, const std::vector<std::uint8_t>& stuck,
                  double stuck_time_s, double dt) {
  double x_scale = 0.0, a_scale = 0.0, ex = 0.0, ea = 0.0;
  Agreement g;
  for (std::size_t n = 0; n < x.size(); ++n) {
    x_scale = std::max(x_scale, std::fabs(r.x_r_m[n]));
    a_scale = std::max(a_scale, std::fabs(r.a_x_m_per_s2[n]));
    ex = std::max(ex, std::fabs(r.x_r_m[n] - x[n]));
    ea = std::max(ea, std::fabs(r.a_x_m_per_s2[n] - a_x[n]));
    if (r.stuck[n] != stuck[n]) ++g.stuck_mismatches;
  }
  g.x = ex / x_scale;
  g.a_x = ea / a_scale;
  g.p = std::fabs(r.stuck_time_s - stuck_time_s) / (dt * static_cast<double>(x.size() - 1));
  return g;
}

std::vector<double> wideband(double duration_s, double dt_s, std::uint64_t seed) {
  GeneratorSpec spec;
  spec.kind = SignalKind::wideband;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = duration_s;
  spec.dt_s = dt_s;
  spec.seed = seed;
  return generate_signal(spec);
}

OscillatorParams scene(FrictionModel model, double den_hartog_k, double damping) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, 1e-3, damping);
  p.kinetic_friction_n = test::kinetic_friction_for_den_hartog(den_hartog_k, p.mass_kg, 0.35);
  p.static_friction_n = 1.2 * p.kinetic_friction_n;
  return p;
}

void check_agreement(const Agreement& g, const char* what) {
  CHECK_TEXT(g.x < kAgreement, StringFromFormat("%s: x %.3e", what, g.x).asCharString());
  CHECK_TEXT(g.a_x < kAgreement, StringFromFormat("%s: a_x %.3e", what, g.a_x).asCharString());
  CHECK_TEXT(g.p < kAgreement, StringFromFormat("%s: p %.3e", what, g.p).asCharString());
  test::note_margin(StringFromFormat("%s: x", what).asCharString(), g.x, kAgreement);
  test::note_margin(StringFromFormat("%s: a_x", what).asCharString(), g.a_x, kAgreement);
  test::note_margin(StringFromFormat("%s: p", what).asCharString(), g.p, kAgreement);
}

}  // namespace

TEST_GROUP(ReferenceAgreesWithIndependentDopri5){};

// 60 s of band-limited Gaussian a_u (0.5-20 Hz, rms 0.35 m/s^2) at dt = 1 ms on the reference
// seat (b = 504): K = 0.8 and K = 1.16 (F_fk = 40 N), F_fs = 1.2 F_fk. Sticks about half the time
// with over a thousand events.
TEST(ReferenceAgreesWithIndependentDopri5, StickSlipOnSixtySecondsOfWidebandInput) {
  const std::vector<double> a_u = wideband(60.0, 1e-3, 1);
  for (double k_factor :
       {0.8, 40.0 / test::kinetic_friction_for_den_hartog(1.0, test::kMassKg, 0.35)}) {
    const OscillatorParams p = scene(FrictionModel::stick_slip, k_factor, test::kDampingNsPerM);
    const ReferenceTrace r = solve_reference(p, a_u);
    const Solution s = dopri5_solution(p, a_u);
    const Agreement g = compare(r, s.x, s.a_x, s.stuck, s.stuck_time_s, p.dt_s);
    check_agreement(g, StringFromFormat("stick-slip K = %.2f vs dopri5", k_factor).asCharString());
    const double p_stick = r.stuck_time_s / 60.0;
    CHECK(p_stick > 0.2 && p_stick < 0.9);
    CHECK(r.events > 500);
    LONGS_EQUAL(static_cast<long>(s.events), static_cast<long>(r.events));
    LONGS_EQUAL(0, static_cast<long>(g.stuck_mismatches));
  }
}

// Undamped (b = 0): the hardest case for error growth, every excursion ends in a stick.
TEST(ReferenceAgreesWithIndependentDopri5, UndampedStickSlip) {
  const std::vector<double> a_u = wideband(20.0, 1e-3, 2);
  const OscillatorParams p = scene(FrictionModel::stick_slip, 0.8, 0.0);
  const ReferenceTrace r = solve_reference(p, a_u);
  const Solution s = dopri5_solution(p, a_u);
  check_agreement(compare(r, s.x, s.a_x, s.stuck, s.stuck_time_s, p.dt_s), "undamped stick-slip");
  LONGS_EQUAL(static_cast<long>(s.events), static_cast<long>(r.events));
}

// Stribeck (v_S = 1 cm/s): the solver's adaptive (Cash-Karp) path with its event search.
TEST(ReferenceAgreesWithIndependentDopri5, StribeckOnTwentySeconds) {
  const std::vector<double> a_u = wideband(20.0, 1e-3, 3);
  OscillatorParams p = scene(FrictionModel::stribeck, 0.8, test::kDampingNsPerM);
  p.stribeck_velocity_m_per_s = 0.01;
  const ReferenceTrace r = solve_reference(p, a_u);
  const Solution s = dopri5_solution(p, a_u);
  check_agreement(compare(r, s.x, s.a_x, s.stuck, s.stuck_time_s, p.dt_s), "stribeck vs dopri5");
  CHECK(r.events > 100);
  LONGS_EQUAL(static_cast<long>(s.events), static_cast<long>(r.events));
}

// The four smoothed signum forms (c = 1000 s/m): smooth ODEs, no events.
TEST(ReferenceAgreesWithIndependentDopri5, SmoothLaws) {
  const std::vector<double> a_u = wideband(5.0, 1e-3, 4);
  for (SmoothingLaw law :
       {SmoothingLaw::atan, SmoothingLaw::tanh, SmoothingLaw::erf, SmoothingLaw::rational}) {
    OscillatorParams p = scene(FrictionModel::smooth, 0.8, test::kDampingNsPerM);
    p.smoothing = law;
    const ReferenceTrace r = solve_reference(p, a_u);
    const Solution s = dopri5_solution(p, a_u);
    check_agreement(compare(r, s.x, s.a_x, s.stuck, s.stuck_time_s, p.dt_s),
                    StringFromFormat("smooth %s vs dopri5", smoothing_name(law)).asCharString());
    CHECK_EQUAL(0u, r.events);
  }
}

// Laws that change over a small velocity (Stribeck v_S = 0.12 mm/s; tanh with c = 5000 s/m) at
// coarse sample intervals, where the adaptive steps are long: the step error control must hold.
// (Hence Dopri5 as the independent solver: Runge-Kutta-Fehlberg 7(8) is 2e-5 off here.)
TEST(ReferenceAgreesWithIndependentDopri5, SharpLawsAtCoarseSampleIntervals) {
  OscillatorParams stribeck = scene(FrictionModel::stribeck, 0.0, 0.0);
  stribeck.dt_s = 3.668e-3;
  stribeck.kinetic_friction_n = 6.41;
  stribeck.static_friction_n = 10.5;
  stribeck.stribeck_velocity_m_per_s = 1.234e-4;
  OscillatorParams smooth = scene(FrictionModel::smooth, 0.0, 100.8);
  smooth.dt_s = 0.0547;
  smooth.kinetic_friction_n = 11.3;
  smooth.smoothing = SmoothingLaw::tanh;
  smooth.smoothing_constant_s_per_m = 4717.0;
  for (const OscillatorParams& p : {stribeck, smooth}) {
    const auto count = static_cast<std::size_t>(5.0 / p.dt_s) + 1;
    const std::vector<double> a_u = test::make_lorry_signal(71, 1.47).sample(p.dt_s, count);
    const ReferenceTrace r = solve_reference(p, a_u);
    const Solution s = dopri5_solution(p, a_u);
    check_agreement(
        compare(r, s.x, s.a_x, s.stuck, s.stuck_time_s, p.dt_s),
        StringFromFormat("%s at dt = %g s", model_name(p.model), p.dt_s).asCharString());
    LONGS_EQUAL(static_cast<long>(s.events), static_cast<long>(r.events));
  }
}

TEST_GROUP(ReferenceAgreesWithCoreExact){};

// The core's exact integrator (matrix exponential, dyadic event search) on the same 60 s scene:
// two different exact methods agree to ~1e-13.
TEST(ReferenceAgreesWithCoreExact, StickSlipOnSixtySecondsOfWidebandInput) {
  const std::vector<double> a_u = wideband(60.0, 1e-3, 1);
  const OscillatorParams p = scene(FrictionModel::stick_slip, 0.8, test::kDampingNsPerM);
  Oscillator<double, CoulombStickSlip> core;
  const ConfigResult configured = core.configure(p);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  core.reset(0.0, 0.0, a_u[0]);
  std::vector<double> x(a_u.size()), a_x(a_u.size());
  std::vector<std::uint8_t> stuck(a_u.size());
  double stuck_time = 0.0;
  const auto first = core.current();
  x[0] = first.x_r_m;
  a_x[0] = first.a_x_m_per_s2;
  stuck[0] = first.stuck ? 1 : 0;
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const auto out = core.step(a_u[n]);
    x[n] = out.x_r_m;
    a_x[n] = out.a_x_m_per_s2;
    stuck[n] = out.stuck ? 1 : 0;
    stuck_time += out.stuck_time_s;
  }
  const ReferenceTrace r = solve_reference(p, a_u);
  const Agreement g = compare(r, x, a_x, stuck, stuck_time, p.dt_s);
  CHECK(g.x < 1e-12);
  CHECK(g.a_x < 1e-12);
  CHECK(g.p < 1e-12);
  LONGS_EQUAL(0, static_cast<long>(g.stuck_mismatches));
  test::note_margin("core exact vs reference: x", g.x, 1e-12);
  test::note_margin("core exact vs reference: a_x", g.a_x, 1e-12);
  test::note_margin("core exact vs reference: p", g.p, 1e-12);
}

TEST_GROUP(ReferenceIntegratedPathMatchesClosedForm){};

// Stribeck with F_fs = F_fk is Coulomb stick-slip with F_fs = F_fk (= signum's Filippov
// solution): the adaptive path with its event search must reproduce the closed-form path.
TEST(ReferenceIntegratedPathMatchesClosedForm, FlatStribeckIsStickSlip) {
  const std::vector<double> a_u = wideband(20.0, 1e-3, 5);
  OscillatorParams stribeck = scene(FrictionModel::stribeck, 0.8, test::kDampingNsPerM);
  stribeck.static_friction_n = stribeck.kinetic_friction_n;
  OscillatorParams signum = stribeck;
  signum.model = FrictionModel::signum;
  signum.static_friction_n = 0.0;  // ignored: signum's static friction is F_fk
  const ReferenceTrace integrated = solve_reference(stribeck, a_u);
  const ReferenceTrace closed = solve_reference(signum, a_u);
  const Agreement g = compare(closed, integrated.x_r_m, integrated.a_x_m_per_s2, integrated.stuck,
                              integrated.stuck_time_s, stribeck.dt_s);
  CHECK(g.x < 1e-10);
  CHECK(g.a_x < 1e-10);
  CHECK(g.p < 1e-10);
  CHECK(closed.events > 100);
  LONGS_EQUAL(static_cast<long>(closed.events), static_cast<long>(integrated.events));
  test::note_margin("flat Stribeck (adaptive) vs signum (closed form): x", g.x, 1e-10);
  test::note_margin("flat Stribeck (adaptive) vs signum (closed form): p", g.p, 1e-10);
}

// A smoothed law with F_fk = 0 is the linear seat.
TEST(ReferenceIntegratedPathMatchesClosedForm, FrictionlessSmoothIsLinear) {
  const std::vector<double> a_u = wideband(10.0, 1e-3, 6);
  OscillatorParams smooth = scene(FrictionModel::smooth, 0.0, test::kDampingNsPerM);
  OscillatorParams linear = smooth;
  linear.model = FrictionModel::linear;
  const ReferenceTrace integrated = solve_reference(smooth, a_u, 0.01, -0.05);
  const ReferenceTrace closed = solve_reference(linear, a_u, 0.01, -0.05);
  const Agreement g = compare(closed, integrated.x_r_m, integrated.a_x_m_per_s2, integrated.stuck,
                              integrated.stuck_time_s, linear.dt_s);
  CHECK(g.x < 1e-11);
  CHECK(g.a_x < 1e-11);
  test::note_margin("frictionless smooth (adaptive) vs linear (closed form): x", g.x, 1e-11);
}
