// The seat with end stops in Q7.24 (ScaledEndStopOscillator<Fixed32, Law>: scene units, one tick
// per step with the cubic polynomial of the exact solution inside it). Q7.24 holds the reference
// seat's k dt^2/m = 1.3e-4 to 11 significant bits, so its own distance from double, measured on
// the plain seat (ScaledOscillator) over the same input, is the yardstick of the runs; a single
// contact, where that rounding has no time to act, is held to the format's last places. Figures are
// printed with STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "../core/oracles.hpp"
#include "end_stop_scenarios.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_end_stops.hpp"
#include "stickslip/models/scaled_oscillator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

using namespace test::end_stop;

// The firmware's ranges (a stroke of 0.1 m), which hold the reference seat's friction of 25-30 N
// (with 1 m, F_fk would be below 2^-14 of the force range and configure() refuses it).
OscillatorParams q724_seat(FrictionModel model, double damping, double kinetic_n, double static_n) {
  OscillatorParams p = seat(model, damping, kinetic_n, static_n);
  p.displacement_range_m = 0.1;
  p.input_range_m_per_s2 = 50.0;
  return p;
}

// A scaled model's run on a_u (SI) from rest, as a History in SI.
template <typename Model>
History scaled_history(Model& model, const SceneUnits& units, const std::vector<double>& a_u) {
  History h;
  const double a_unit = units.acceleration_m_per_s2();
  const auto record = [&](const StepOutput<Fixed32>& out) {
    h.x.push_back(out.x_r_m.to_double() * units.length_m);
    h.a_x.push_back(out.a_x_m_per_s2.to_double() * a_unit);
    h.friction.push_back(out.friction_n.to_double() * units.force_n());
    h.stuck.push_back(out.stuck ? 1 : 0);
    h.stuck_fraction.push_back(out.stuck_fraction.to_double());
  };
  model.reset(Fixed32(0.0), Fixed32(0.0), Fixed32(a_u[0] / a_unit));
  record(model.current());
  for (std::size_t n = 1; n < a_u.size(); ++n) {
    const StepOutput<Fixed32> out = model.step(Fixed32(a_u[n] / a_unit));
    h.stuck_s += out.stuck_fraction.to_double() * kDt;
    record(out);
  }
  h.saturated = model.saturated_steps();
  h.resets = model.state_resets();
  h.budget_exhausted = model.event_budget_exhausted();
  return h;
}

template <typename Law>
History with_stops_q724(const OscillatorParams& p, const EndStopParams& s,
                        const std::vector<double>& a_u, SceneUnits* units_out = nullptr) {
  ScaledEndStopOscillator<Fixed32, Law> scaled;
  const ConfigResult configured = scaled.configure(p, s);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  History h = scaled_history(scaled.oscillator(), scaled.units(), a_u);
  h.contacts = scaled.oscillator().contacts();
  if (units_out != nullptr) *units_out = scaled.units();
  return h;
}

template <typename Law>
History plain_q724(const OscillatorParams& p, const std::vector<double>& a_u,
                   SceneUnits* units_out = nullptr) {
  ScaledOscillator<Fixed32, Law> scaled;
  const ConfigResult configured = scaled.configure(p);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  History h = scaled_history(scaled.oscillator(), scaled.units(), a_u);
  if (units_out != nullptr) *units_out = scaled.units();
  return h;
}

template <typename Model>
History double_history(Model& model, const std::vector<double>& a_u) {
  History h = counted_history(model, a_u);
  h.resets = model.state_resets();
  return h;
}

// The Q7.24 runs, with and without stops, and the double ones, for a seat and stops.
struct Runs {
  History with_stops, plain, with_stops_double, plain_double;
  SceneUnits units_with_stops, units_plain;
};

template <typename Law>
Runs run_all(const OscillatorParams& p, const EndStopParams& s, const std::vector<double>& a_u) {
  Runs r;
  r.with_stops = with_stops_q724<Law>(p, s, a_u, &r.units_with_stops);
  r.plain = plain_q724<Law>(p, a_u, &r.units_plain);
  EndStopOscillator<double, Law> stops_double;
  CHECK_TRUE(stops_double.configure(p, s).ok());
  r.with_stops_double = double_history(stops_double, a_u);
  Oscillator<double, Law> plain_double;
  CHECK_TRUE(plain_double.configure(p).ok());
  r.plain_double = run_history(plain_double, a_u);
  return r;
}

}  // namespace

TEST_GROUP(EndStopQ724){};

// Out of reach (travel 0.09 m of the 0.1 m range, the motion a few millimetres) the seat with stops
// is the plain Q7.24 seat in the same units: the frictionless one bit for bit (both take the
// whole step's map and nothing else), the stick-slip one to the rounding of its events (both
// solve the same cubic, formed in a different order): within a tenth of the plain seat's own
// distance from double, in x_r, a_x, T_ax and p.
TEST(EndStopQ724, StopsOutOfReachAreThePlainQ724Seat) {
  const std::vector<double> a_u = wideband(0.35, 20.0, 5);
  for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
    for (const double damping : {0.0, 504.0}) {
      const bool sticking = model == FrictionModel::stick_slip;
      const OscillatorParams p = q724_seat(model, damping, sticking ? 25.0 : 0.0, 30.0);
      const EndStopParams s = stops(0.09, 2.0e3);
      const Runs r =
          sticking ? run_all<CoulombStickSlip>(p, s, a_u) : run_all<NoFriction>(p, s, a_u);
      const Deviation spread = deviation(r.plain, r.plain_double, 20.0);
      const Deviation to_plain = deviation(r.with_stops, r.plain, 20.0);
      print(sticking ? "stick-slip: plain Q7.24 vs double" : "frictionless: plain Q7.24 vs double",
            spread);
      print("  with stops (Q7.24) vs plain Q7.24", to_plain);
      CHECK(r.units_with_stops.length_m == r.units_plain.length_m);
      if (sticking) CHECK(r.plain_double.stuck_s > 1.0);
      CHECK_EQUAL(0u, r.with_stops.contacts);
      CHECK_EQUAL(0u, r.with_stops.saturated);
      CHECK(to_plain.x <= 0.1 * spread.x);
      CHECK(to_plain.a_x <= 0.1 * spread.a_x);
      CHECK(to_plain.t_ax <= std::max(0.1 * spread.t_ax, 1e-9));
      CHECK(to_plain.p <= std::max(0.1 * spread.p, 1e-9));
      if (!sticking) CHECK(r.with_stops.x == r.plain.x);
    }
  }
}

namespace {

// The largest |x_r| difference of two histories, relative to the largest |x_r| of the second.
double largest_x_difference(const History& got, const History& want) {
  double worst = 0.0, amplitude = 0.0;
  for (std::size_t n = 0; n < want.x.size(); ++n) {
    worst = std::max(worst, std::fabs(got.x[n] - want.x[n]));
    amplitude = std::max(amplitude, std::fabs(want.x[n]));
  }
  return worst / amplitude;
}

}  // namespace

// White noise of +-12 m/s^2, a new level every sample, out of reach: v_r often crosses 0 and back
// inside one step, which the scan now hands to the step's cubic. The seat with stops stays as
// close to the double seat as the plain Q7.24 seat does (at most 1.8 times its distance, measured;
// before the scan looked for such dips, up to 35 times, damped), damped and undamped, 6 seeds.
TEST(EndStopQ724, StopsOutOfReachFollowDoubleAsThePlainQ724SeatWhereVrDipsThroughZero) {
  for (const double damping : {0.0, 504.0}) {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const std::vector<double> a_u = white_noise(12.0, seed);
      const OscillatorParams p = q724_seat(FrictionModel::stick_slip, damping, 25.0, 30.0);
      const Runs r = run_all<CoulombStickSlip>(p, stops(0.09, 2.0e3), a_u);
      const double spread = largest_x_difference(r.plain, r.plain_double);
      const double with_stops = largest_x_difference(r.with_stops, r.plain_double);
      test::note_margin("q7.24 out of reach on white noise, x vs double / plain's", with_stops,
                        2.0 * spread);
      CHECK_EQUAL(0u, r.with_stops.contacts);
      CHECK_EQUAL(0u, r.with_stops.saturated);
      CHECK(r.plain_double.stuck_s > 0.0);  // sticks of fractions of a step: the stick paths ran
      CHECK(with_stops <= 2.0 * spread);
    }
  }
}

// In contact (stops at the RMS free stroke, 2e5 N/m, damped), against the double model with
// stops, two seeds. The damped seat (b = 504 N s/m) makes the same contacts, and its x_r and T_ax
// stay within twice the plain Q7.24 seat's distance from the plain double one on the same input
// (measured at most 1.7 and 0.8 times), p within that or 1e-5 (0.2 ms of stuck time in 20 s;
// measured 3.1e-6): the stops add no error beyond the format's. (a_x is not compared with the plain
// seat's: in contact it carries x_r's error times (k + k_s)/m, 18 times the free seat's.) Without
// damping in the seat every rounding difference is carried on, as the plain seat's own spread
// shows (x_r 1e-2 vs 2e-4 damped), and a grazing contact may be seen by one run only: contacts
// within one of double's, T_ax and p within docs/EMBEDDED.md's fixed-point targets (1 %, 0.01;
// measured T_ax 5.8e-4, p 2.4e-5 at most). Nothing saturates, no event is lost.
TEST(EndStopQ724, ContactFollowsTheDoubleModelAsThePlainQ724SeatDoes) {
  for (const std::uint64_t seed : {13u, 29u}) {
    const std::vector<double> a_u = wideband(2.0, 20.0, seed);
    for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
      for (const double damping : {0.0, 504.0}) {
        const bool sticking = model == FrictionModel::stick_slip;
        const OscillatorParams p = q724_seat(model, damping, sticking ? 25.0 : 0.0, 30.0);
        const EndStopParams s = stops(sticking ? rms_free_stroke<CoulombStickSlip>(p, a_u)
                                               : rms_free_stroke<NoFriction>(p, a_u),
                                      2.0e3);
        const Runs r =
            sticking ? run_all<CoulombStickSlip>(p, s, a_u) : run_all<NoFriction>(p, s, a_u);
        const Deviation spread = deviation(r.plain, r.plain_double, 20.0);
        const Deviation d = deviation(r.with_stops, r.with_stops_double, 20.0);
        print(
            sticking ? "stick-slip: plain Q7.24 vs double" : "frictionless: plain Q7.24 vs double",
            spread);
        print("  in contact: with stops (Q7.24) vs double", d);
        const auto contacts = static_cast<long>(r.with_stops.contacts);
        const auto want_contacts = static_cast<long>(r.with_stops_double.contacts);
        CHECK(want_contacts > 10);
        CHECK_EQUAL(0u, r.with_stops.saturated);
        CHECK_EQUAL(0u, r.with_stops.budget_exhausted);
        CHECK_EQUAL(0u, r.with_stops.resets);
        if (damping > 0.0) {
          CHECK_EQUAL(want_contacts, contacts);
          CHECK(d.x <= 2.0 * spread.x);
          CHECK(d.t_ax <= 2.0 * spread.t_ax);
          CHECK(d.p <= std::max(2.0 * spread.p, 1e-5));
        } else {
          CHECK(std::labs(contacts - want_contacts) <= 1);
        }
        CHECK(d.t_ax <= 0.01);
        CHECK(d.p <= 0.01);
      }
    }
  }
}

// One step into a stop, from states just short of it (x_r within a step's travel of the edge,
// moving towards it, the floor's acceleration random), free and slipping against Coulomb friction:
// the contact instant, and the state at the step's end, are the double model's to a few units of
// Q7.24's last place (2^-24 of the scene's length unit L). The instant is compared as the distance
// it moves the seat (instant error times v_r, in units of the last place). The inputs (x_r, v_r,
// a_u, travel) and every coefficient are each rounded to half a unit, and the cubic's evaluation
// adds about 1.5: 8 units allow for that (measured at most 4.8, the state's x_r 5.9). v_r also
// carries the rounding of k dt^2/m (half a unit, 11 significant bits for the reference seat) times
// x_r, at the stop travel / L = 16 units: 8 more units (measured 11.7).
TEST(EndStopQ724, LocatesAContactToTheFormatsLastPlaces) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_instant = 0.0, worst_x = 0.0, worst_v = 0.0, k_rounding = 0.0;
  int contacts = 0;
  for (const FrictionModel model : {FrictionModel::linear, FrictionModel::stick_slip}) {
    const bool sticking = model == FrictionModel::stick_slip;
    const OscillatorParams p = q724_seat(model, 504.0, sticking ? 25.0 : 0.0, 30.0);
    const EndStopParams s = stops(0.05, 2.0e3);
    for (int i = 0; i < 200; ++i) {
      const double side = i % 2 == 0 ? 1.0 : -1.0;
      const double v0 = side * (0.05 + 0.5 * unit(rng));
      const double x0 = side * 0.05 - v0 * kDt * unit(rng);
      const double a0 = 20.0 * (unit(rng) - 0.5), a1 = 20.0 * (unit(rng) - 0.5);
      const auto one_step = [&](auto law) {
        using Law = decltype(law);
        EndStopOscillator<double, Law> exact;
        CHECK_TRUE(exact.configure(p, s).ok());
        ScaledEndStopOscillator<Fixed32, Law> scaled;
        CHECK_TRUE(scaled.configure(p, s).ok());
        const SceneUnits u = scaled.units();
        const double lsb = std::ldexp(1.0, -24);
        exact.reset(x0, v0, a0);
        exact.step(a1);
        auto& q = scaled.oscillator();
        const double a_unit = u.acceleration_m_per_s2();
        q.reset(Fixed32(x0 / u.length_m), Fixed32(v0 / u.velocity_m_per_s()), Fixed32(a0 / a_unit));
        const StepOutput<Fixed32> out = q.step(Fixed32(a1 / a_unit));
        const double want_at = exact.last_step_contacts().first_contact_s / kDt;
        const double got_at = q.last_step_contacts().first_contact_s.to_double();
        CHECK_EQUAL(exact.last_step_contacts().contact_events,
                    q.last_step_contacts().contact_events);
        if (exact.last_step_contacts().contact_events == 0) return;
        ++contacts;
        const double v_scene = std::fabs(v0) / u.velocity_m_per_s();
        k_rounding = 0.5 * s.travel_m / u.length_m;  // in units of the last place
        worst_instant = std::max(worst_instant, std::fabs(got_at - want_at) * v_scene / lsb);
        worst_x =
            std::max(worst_x, std::fabs(out.x_r_m.to_double() - exact.x_r() / u.length_m) / lsb);
        worst_v = std::max(
            worst_v,
            std::fabs(out.v_r_m_per_s.to_double() - exact.v_r() / u.velocity_m_per_s()) / lsb);
      };
      if (sticking) {
        one_step(CoulombStickSlip{});
      } else {
        one_step(NoFriction{});
      }
    }
  }
  if (std::getenv("STICKSLIP_TEST_MARGINS") != nullptr) {
    std::printf(
        "\n    [figure] %d contacts: instant %.2f, x_r %.2f, v_r %.2f units of the last place",
        contacts, worst_instant, worst_x, worst_v);
  }
  CHECK(contacts > 300);
  CHECK(worst_instant <= 8.0);
  CHECK(worst_x <= 8.0);
  CHECK(k_rounding > 0.0);
  CHECK(worst_v <= 8.0 + k_rounding);
}

// A stop the cubic search is not verified for is refused by configure(), naming the stop's
// parameter in scene units: damping of 1e5 N s/m makes (b/m) dt = 1.14 in contact, which double
// takes.
TEST(EndStopQ724, ConfigureRefusesAStopBeyondTheCubicSearch) {
  const OscillatorParams p = q724_seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  EndStopParams s = stops(0.05, 1.0e5);
  EndStopOscillator<double, CoulombStickSlip> in_double;
  CHECK_TRUE(in_double.configure(p, s).ok());
  ScaledEndStopOscillator<Fixed32, CoulombStickSlip> model;
  const ConfigResult refused = model.configure(p, s);
  CHECK_FALSE(refused.ok());
  STRCMP_CONTAINS("end_stop_damping_ns_per_m: in scene units", refused.message.c_str());
  STRCMP_CONTAINS("in contact, (b/m) dt + (k/m) dt^2/2 = 1.1", refused.message.c_str());
}

// A travel beyond the displacement range would saturate in scene units and silently move the
// stops: configure() refuses it, naming the stop's parameter (the stops out of reach are a travel
// within the range, as StopsOutOfReachAreThePlainQ724Seat takes).
TEST(EndStopQ724, ConfigureRefusesATravelBeyondTheDisplacementRange) {
  const OscillatorParams p = q724_seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  ScaledEndStopOscillator<Fixed32, CoulombStickSlip> model;
  const ConfigResult refused = model.configure(p, stops(10.0, 2.0e3));
  CHECK_FALSE(refused.ok());
  STRCMP_CONTAINS("end_stop_travel_m: in scene units", refused.message.c_str());
  STRCMP_CONTAINS("raise displacement_range_m to the travel", refused.message.c_str());
  CHECK_TRUE(model.configure(p, stops(0.1, 2.0e3)).ok());
}
