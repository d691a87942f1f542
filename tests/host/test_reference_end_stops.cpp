// The reference solver with end stops against an independent method written here: Boost.Odeint's
// Dormand-Prince 5(4) with dense output (tolerances 1e-14 relative, 1e-17 absolute) on the
// piecewise right-hand side, restarted at every sample and every event; contact, release and
// v_r = 0 found by scanning the dense output and bisecting it, break-away by bisection on
// |F_L| = F_fs - no closed form, no Newton, no shared code; with an actuator force, its f_a/m
// enters the right-hand side as written (held over each interval); Stribeck friction as its
// formula, F_f = (F_fk + (F_fs - F_fk) exp(-(v_r/v_S)^2)) d. Worst errors are printed with
// STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <boost/numeric/odeint.hpp>

#include "../core/oracles.hpp"
#include "stickslip/host/error.hpp"
#include "stickslip/host/run/reference_solver.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

namespace odeint = boost::numeric::odeint;
using State = std::array<double, 2>;

struct Solution {
  std::vector<double> x, a_x;
  std::vector<std::uint8_t> stuck;
  double stuck_time_s = 0.0;
  std::uint64_t contacts = 0;
};

int region_of(double x, double travel) {
  return x > travel ? 1 : (x < -travel ? -1 : 0);
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

// Dormand-Prince with dense output in the current region and slip direction (the right-hand side
// is smooth there), restarted at every sample and event. The dense output only locates instants;
// the state there is integrated again from the start of its step.
Solution dopri5_solution(const OscillatorParams& p, const EndStopParams& s,
                         const std::vector<double>& a_u, const std::vector<double>* f_a = nullptr) {
  const bool stribeck = p.model == FrictionModel::stribeck;
  const bool sticking = p.model == FrictionModel::stick_slip || stribeck;
  const double dt = p.dt_s, m = p.mass_kg, k = p.stiffness_n_per_m, b = p.damping_ns_per_m;
  const double fk = sticking ? p.kinetic_friction_n : 0.0,
               fs = sticking ? p.static_friction_n : 0.0;
  const double ks = s.stiffness_n_per_m, bs = s.damping_ns_per_m, travel = s.travel_m;
  Solution out;
  const std::size_t count = a_u.size();
  out.x.resize(count);
  out.a_x.resize(count);
  out.stuck.resize(count);
  State y{0.0, 0.0};
  int c = 0;
  const auto stop = [&](double x, double v, int region) {
    return region == 0 ? 0.0 : ks * (x - region * travel) + bs * v;
  };
  const auto force = [&](std::size_t n) { return f_a == nullptr ? 0.0 : (*f_a)[n]; };
  // The slip friction in direction dir at velocity v.
  const auto friction = [&](double v, double dir) {
    if (!stribeck) return fk * dir;
    const double r = std::fabs(v) / p.stribeck_velocity_m_per_s;
    // exp(-400) is nothing against F_fk; beyond it exp() would only raise underflow.
    return (fk + (r > 20.0 ? 0.0 : (fs - fk) * std::exp(-r * r))) * dir;
  };
  // F_L = f_a - (m a_u + k x_r + F_stop), with the force of the interval in hand.
  double f_now = force(0);
  const auto limit_at = [&](double a_u_now) {
    return f_now - (m * a_u_now + k * y[0] + stop(y[0], 0, c));
  };
  double d = sticking && std::fabs(limit_at(a_u[0])) <= fs ? 0.0 : 1.0;
  if (d != 0.0 && limit_at(a_u[0]) < 0.0) d = -1.0;
  const auto record = [&](std::size_t n) {
    out.x[n] = y[0];
    out.stuck[n] = d == 0.0 ? 1 : 0;
    out.a_x[n] =
        d == 0.0 ? a_u[n]
                 : (force(n) - (k * y[0] + b * y[1] + stop(y[0], y[1], c) + friction(y[1], d))) / m;
  };
  record(0);
  double h = dt / 8.0;
  for (std::size_t n = 1; n < count; ++n) {
    const double a0 = a_u[n - 1], a1 = a_u[n];
    f_now = force(n);
    const auto input = [&](double t) { return a0 + (a1 - a0) * (t / dt); };
    double t = 0.0;
    for (int guard = 0; t < dt && guard < 1000; ++guard) {
      if (d == 0.0) {
        const auto limit = [&](double at) { return limit_at(input(at)); };
        if (std::fabs(limit(t)) > fs) {  // the force changed at the sample: F_L jumped
          d = limit(t) > 0.0 ? 1.0 : -1.0;
          y[1] = 0.0;
          continue;
        }
        if (std::fabs(limit(dt)) <= fs) {
          out.stuck_time_s += dt - t;
          break;
        }
        const double dir = limit(dt) > 0.0 ? 1.0 : -1.0;
        double lo = t, hi = dt;
        for (int i = 0; i < 200 && hi - lo > 1e-16 * dt; ++i) {
          const double mid = 0.5 * (lo + hi);
          (dir * limit(mid) - fs > 0.0 ? hi : lo) = mid;
        }
        out.stuck_time_s += hi - t;
        t = hi;
        d = dir;
        y[1] = 0.0;
        continue;
      }
      const int region = c;
      const double dir = d;
      const auto system = [&, region, dir](const State& z, State& dz, double at) {
        dz[0] = z[1];
        dz[1] =
            (f_now - (k * z[0] + b * z[1] + stop(z[0], z[1], region) + friction(z[1], dir))) / m -
            input(at);
      };
      // The mode ends where the region changes or (sticking) v_r d reaches 0.
      const auto ends = [&](const State& z) {
        const int r = region_of(z[0], travel);
        const bool left = region == 0 ? r != 0 : region * z[0] < travel;
        return left || (sticking && dir * z[1] <= 0.0);
      };
      auto stepper = odeint::make_dense_output(1e-17, 1e-14, odeint::runge_kutta_dopri5<State>());
      stepper.initialize(y, t, std::min(h, dt - t));
      bool event = false;
      State at_event{};  // the dense output's state at the event: which boundary it was
      for (;;) {
        const auto [t0, t1] = stepper.do_step(system);
        h = stepper.current_time_step();
        const double end = std::min(t1, dt);
        double crossing = -1.0, left = t0;
        for (int j = 1; j <= 16 && crossing < 0.0; ++j) {
          const double right = j == 16 ? end : t0 + (end - t0) * j / 16.0;
          State z{};
          stepper.calc_state(right, z);
          if (ends(z)) {
            double lo = left, hi = right;
            for (int i = 0; i < 200 && hi - lo > 1e-16 * dt; ++i) {
              const double mid = 0.5 * (lo + hi);
              stepper.calc_state(mid, z);
              (ends(z) ? hi : lo) = mid;
            }
            crossing = hi;
            stepper.calc_state(hi, at_event);
          }
          left = right;
        }
        if (crossing >= 0.0) {
          land(system, stepper.previous_state(), t0, crossing, y);
          t = crossing;
          event = true;
          break;
        }
        if (t1 >= dt) {
          land(system, stepper.previous_state(), t0, dt, y);
          t = dt;
          break;
        }
      }
      if (!event) continue;
      const int r = region_of(at_event[0], travel);
      if (region == 0 && r != 0) {
        c = r;
        y[0] = r * travel;  // on the boundary, continuing into the stop
        ++out.contacts;
      } else if (region != 0 && region * at_event[0] < travel) {
        c = 0;
        y[0] = region * travel;
      } else if (sticking) {
        y[1] = 0.0;
        const double limit = limit_at(input(t));
        d = std::fabs(limit) <= fs ? 0.0 : (limit > 0.0 ? 1.0 : -1.0);
      }
    }
    record(n);
  }
  return out;
}

struct Agreement {
  double x = 0.0, a_x = 0.0, p = 0.0;
  std::size_t stuck_mismatches = 0;
};

Agreement compare(const ReferenceTrace& r, const Solution& s, double dt) {
  double x_scale = 0.0, a_scale = 0.0, ex = 0.0, ea = 0.0;
  Agreement g;
  for (std::size_t n = 0; n < s.x.size(); ++n) {
    x_scale = std::max(x_scale, std::fabs(r.x_r_m[n]));
    a_scale = std::max(a_scale, std::fabs(r.a_x_m_per_s2[n]));
    ex = std::max(ex, std::fabs(r.x_r_m[n] - s.x[n]));
    ea = std::max(ea, std::fabs(r.a_x_m_per_s2[n] - s.a_x[n]));
    if (r.stuck[n] != s.stuck[n]) ++g.stuck_mismatches;
  }
  g.x = ex / x_scale;
  g.a_x = ea / a_scale;
  g.p = std::fabs(r.stuck_time_s - s.stuck_time_s) / (dt * static_cast<double>(s.x.size() - 1));
  return g;
}

std::vector<double> wideband(double rms, double duration_s, std::uint64_t seed) {
  GeneratorSpec spec;
  spec.kind = SignalKind::wideband;
  spec.rms_m_per_s2 = rms;
  spec.duration_s = duration_s;
  spec.dt_s = 1e-3;
  spec.seed = seed;
  return generate_signal(spec);
}

OscillatorParams seat(FrictionModel model, double damping, double kinetic_n, double static_n) {
  OscillatorParams p = test::reference_params(model, Integrator::exact, 1e-3, damping);
  p.kinetic_friction_n = kinetic_n;
  p.static_friction_n = static_n;
  return p;
}

// The stops at half the stroke the seat reaches without them: contacts most cycles.
double half_free_stroke(const OscillatorParams& p, const std::vector<double>& a_u) {
  const ReferenceTrace free = solve_reference(p, a_u);
  double reach = 0.0;
  for (const double x : free.x_r_m) reach = std::max(reach, std::fabs(x));
  return 0.5 * reach;
}

EndStopParams stops(double travel_m, double damping) {
  EndStopParams s;
  s.travel_m = travel_m;
  s.stiffness_n_per_m = 2.0e5;
  s.damping_ns_per_m = damping;
  return s;
}

// The methods differ by the adaptive integrator's error (1e-14 relative per step) grown over the
// run: 1e-14 of the amplitude with damping, 2e-11 on the undamped stick-slip seat (nothing decays
// the differences between its contacts); 1e-10 bounds both.
constexpr double kAgreement = 1e-10;

void check(const ReferenceTrace& r, const Solution& s, const char* what) {
  const Agreement g = compare(r, s, 1e-3);
  test::note_margin(what, std::max(g.x, g.a_x), kAgreement);
  if (std::getenv("STICKSLIP_TEST_MARGINS") != nullptr)
    std::printf(" contacts %llu/%llu", (unsigned long long)r.contacts,
                (unsigned long long)s.contacts);
  CHECK_TEXT(r.contacts > 10, what);
  CHECK_EQUAL(s.contacts, r.contacts);
  CHECK_TEXT(g.x < kAgreement, StringFromFormat("%s: x %.3e", what, g.x).asCharString());
  CHECK_TEXT(g.a_x < kAgreement, StringFromFormat("%s: a_x %.3e", what, g.a_x).asCharString());
  CHECK_TEXT(g.p < kAgreement, StringFromFormat("%s: p %.3e", what, g.p).asCharString());
  CHECK_EQUAL(0u, g.stuck_mismatches);
}

}  // namespace

TEST_GROUP(ReferenceEndStops){};

TEST(ReferenceEndStops, FrictionlessSeatInContactMatchesDormandPrince) {
  const std::vector<double> a_u = wideband(1.5, 4.0, 7);
  const OscillatorParams p = seat(FrictionModel::linear, 504.0, 0.0, 0.0);
  for (const double stop_damping : {2.0e3, 0.0}) {
    const EndStopParams s = stops(half_free_stroke(p, a_u), stop_damping);
    check(solve_reference(p, s, a_u), dopri5_solution(p, s, a_u),
          stop_damping > 0 ? "frictionless, damped stop" : "frictionless, undamped stop");
  }
}

TEST(ReferenceEndStops, StickSlipSeatInContactMatchesDormandPrince) {
  const std::vector<double> a_u = wideband(2.0, 4.0, 11);
  for (const double damping : {504.0, 0.0}) {
    const OscillatorParams p = seat(FrictionModel::stick_slip, damping, 25.0, 30.0);
    const EndStopParams s = stops(half_free_stroke(p, a_u), damping > 0 ? 2.0e3 : 0.0);
    const ReferenceTrace r = solve_reference(p, s, a_u);
    CHECK(r.events > 10);
    check(r, dopri5_solution(p, s, a_u),
          damping > 0 ? "stick-slip, damped" : "stick-slip, undamped");
  }
}

// With an actuator force held over each interval (steps every 37 samples and two sines, up to
// 60 N: F_L jumps beyond F_fs at some samples), both seats, damped and undamped.
TEST(ReferenceEndStops, ActuatedSeatInContactMatchesDormandPrince) {
  const std::vector<double> a_u = wideband(2.0, 4.0, 19);
  std::vector<double> f_a(a_u.size());
  test::SplitMix64 random(7);
  double level = 0.0;
  for (std::size_t n = 0; n < f_a.size(); ++n) {
    if (n % 37 == 0) level = random.uniform(-40.0, 40.0);
    f_a[n] = level + 20.0 * std::sin(2.0 * test::kPi * 1.7 * static_cast<double>(n) * 1e-3);
  }
  for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
    for (const double damping : {504.0, 0.0}) {
      const bool sticking = model == FrictionModel::stick_slip;
      const OscillatorParams p = seat(model, damping, sticking ? 25.0 : 0.0, sticking ? 30.0 : 0.0);
      // The stops at the RMS stroke of the actuated seat without them.
      double sum = 0.0;
      for (const double x : solve_reference_actuated(p, a_u, f_a).x_r_m) sum += x * x;
      const double stroke = std::sqrt(sum / static_cast<double>(a_u.size()));
      const EndStopParams s = stops(stroke, damping > 0 ? 2.0e3 : 0.0);
      const ReferenceTrace r = solve_reference_actuated(p, s, a_u, f_a);
      if (sticking) CHECK(r.events > 10);
      check(r, dopri5_solution(p, s, a_u, &f_a),
            sticking
                ? (damping > 0 ? "actuated stick-slip, damped" : "actuated stick-slip, undamped")
                : (damping > 0 ? "actuated frictionless, damped"
                               : "actuated frictionless, undamped"));
    }
  }
}

// Stribeck (v_S = 1 cm/s): the solver's adaptive (Cash-Karp) slip phases with the region's
// stop force, against Dormand-Prince on the same right-hand side; damped and undamped.
TEST(ReferenceEndStops, StribeckSeatInContactMatchesDormandPrince) {
  const std::vector<double> a_u = wideband(2.0, 4.0, 11);
  for (const double damping : {504.0, 0.0}) {
    OscillatorParams p = seat(FrictionModel::stribeck, damping, 25.0, 30.0);
    p.stribeck_velocity_m_per_s = 0.01;
    const EndStopParams s = stops(half_free_stroke(p, a_u), damping > 0 ? 2.0e3 : 0.0);
    const ReferenceTrace r = solve_reference(p, s, a_u);
    CHECK(r.events > 10);
    check(r, dopri5_solution(p, s, a_u), damping > 0 ? "stribeck, damped" : "stribeck, undamped");
  }
}

// A flat Stribeck law (F_fs = F_fk) is stick-slip: the adaptive path with the stops must
// reproduce the closed-form path with them.
TEST(ReferenceEndStops, FlatStribeckWithStopsIsStickSlipWithStops) {
  const std::vector<double> a_u = wideband(2.0, 4.0, 11);
  OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 25.0);
  const EndStopParams s = stops(half_free_stroke(p, a_u), 2.0e3);
  const ReferenceTrace closed = solve_reference(p, s, a_u);
  p.model = FrictionModel::stribeck;
  const ReferenceTrace integrated = solve_reference(p, s, a_u);
  CHECK(closed.contacts > 10);
  CHECK(closed.events > 10);
  CHECK_EQUAL(closed.contacts, integrated.contacts);
  CHECK_EQUAL(closed.events, integrated.events);
  Solution as_solution;
  as_solution.x = integrated.x_r_m;
  as_solution.a_x = integrated.a_x_m_per_s2;
  as_solution.stuck = integrated.stuck;
  as_solution.stuck_time_s = integrated.stuck_time_s;
  as_solution.contacts = integrated.contacts;
  const Agreement g = compare(closed, as_solution, 1e-3);
  test::note_margin("flat stribeck (adaptive) vs stick-slip (closed form), stops", g.x, kAgreement);
  CHECK(g.x < kAgreement);
  CHECK(g.a_x < kAgreement);
  CHECK(g.p < kAgreement);
  CHECK_EQUAL(0u, g.stuck_mismatches);
}

// Out of reach the stops change nothing: the same trace as the reference without them.
TEST(ReferenceEndStops, StopsOutOfReachGiveTheReferenceWithoutStops) {
  const std::vector<double> a_u = wideband(0.35, 20.0, 3);
  for (const FrictionModel model : {FrictionModel::linear, FrictionModel::stick_slip}) {
    const OscillatorParams p = seat(model, 0.0, 25.0, 30.0);
    const ReferenceTrace with = solve_reference(p, stops(10.0, 0.0), a_u);
    const ReferenceTrace without = solve_reference(p, a_u);
    CHECK_EQUAL(0u, with.contacts);
    CHECK_EQUAL(without.events, with.events);
    // The frictionless path without stops takes whole samples, the one with stops ends pieces
    // where v_r turns: the same closed form, rounded (long double) in other places.
    double x_scale = 0.0, a_scale = 0.0, ex = 0.0, ea = 0.0;
    for (std::size_t n = 0; n < a_u.size(); ++n) {
      x_scale = std::max(x_scale, std::fabs(without.x_r_m[n]));
      a_scale = std::max(a_scale, std::fabs(without.a_x_m_per_s2[n]));
      ex = std::max(ex, std::fabs(without.x_r_m[n] - with.x_r_m[n]));
      ea = std::max(ea, std::fabs(without.a_x_m_per_s2[n] - with.a_x_m_per_s2[n]));
    }
    test::note_margin("out of reach, x", ex / x_scale, 1e-14);
    CHECK(ex <= 1e-14 * x_scale);
    CHECK(ea <= 1e-14 * a_scale);
  }
}

TEST(ReferenceEndStops, RefusesTheSmoothLawsAndBadStops) {
  const std::vector<double> a_u(10, 0.0);
  OscillatorParams p = seat(FrictionModel::smooth, 504.0, 25.0, 30.0);
  CHECK_THROWS(ConfigurationError, solve_reference(p, stops(0.01, 0.0), a_u));
  p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  CHECK_THROWS(ConfigurationError, solve_reference(p, stops(-0.01, 0.0), a_u));
}

// Every bad input gets the plain seat's one line, naming the value: the two solvers share their
// input checks.
TEST(ReferenceEndStops, RefusesBadInputsWithThePlainSolversMessage) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  const EndStopParams s = stops(0.01, 0.0);
  const auto message = [](const auto& solve) {
    try {
      solve();
    } catch (const HostError& error) {
      return std::string(error.what());
    }
    return std::string("(accepted)");
  };
  struct Bad {
    std::vector<double> a_u, f_a;
    double x0, v0;
    const char* names;
  };
  const double nan = std::nan("");
  const Bad cases[] = {
      {{}, {}, 0.0, 0.0, "no samples"},
      {{0.0, 1.0, nan, 0.0}, {}, 0.0, 0.0, "a_u[2] = nan"},
      {{0.0, 1.0, 0.0}, {0.0, 1.0}, 0.0, 0.0, "2 actuator forces for 3 input samples"},
      {{0.0, 1.0, 0.0}, {0.0, HUGE_VAL, 0.0}, 0.0, 0.0, "f_a[1] = inf"},
      {{0.0, 1.0}, {}, 0.0, -HUGE_VAL, "v0 = -inf"},
  };
  for (const Bad& bad : cases) {
    const std::string with_stops =
        message([&] { solve_reference_actuated(p, s, bad.a_u, bad.f_a, bad.x0, bad.v0); });
    const std::string without =
        message([&] { solve_reference_actuated(p, bad.a_u, bad.f_a, bad.x0, bad.v0); });
    STRCMP_CONTAINS(bad.names, with_stops.c_str());
    STRCMP_EQUAL(without.c_str(), with_stops.c_str());
  }
}
