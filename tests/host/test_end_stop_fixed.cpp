// The seat with end stops in fixed point (EndStopOscillator<Fixed, Law>, Q23.40): out of reach
// of the stops against the plain fixed-point oscillator, in contact against the double model
// (T_ax and p within docs/EMBEDDED.md's fixed-point targets: T_ax 1 %, p 0.01). Figures are
// printed with STICKSLIP_TEST_MARGINS=1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../core/oracles.hpp"
#include "end_stop_scenarios.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

// The shared scenes, seats and histories (end_stop_scenarios.hpp).
using namespace test::end_stop;

template <typename T, typename Law>
History end_stop_history(const OscillatorParams& p, const EndStopParams& s,
                         const std::vector<double>& a_u) {
  EndStopOscillator<T, Law> model;
  const ConfigResult configured = model.configure(p, s);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
  History h = counted_history(model, a_u);
  h.resets = model.state_resets();
  if constexpr (ScalarTraits<T>::kTracksSaturation) h.saturated = model.saturated_steps();
  return h;
}

}  // namespace

TEST_GROUP(EndStopFixedPoint){};

// Out of reach (10 m of travel) the fixed-point seat with stops is the plain fixed-point
// oscillator to the format's rounding: the two locate events on different grids (dt/2^16 here,
// dt/2^10 there), each rounding in Q23.40, so the yardstick is how far the plain fixed-point run
// is from the double one. The model with stops stays within 2.5 times that spread in x_r, a_x, T_ax
// and p (measured at most 1.9 times; T_ax and p: or 1e-9, where the spread is smaller).
TEST(EndStopFixedPoint, StopsOutOfReachEqualThePlainFixedOscillatorToItsRounding) {
  const std::vector<double> a_u = wideband(0.35, 20.0, 5);
  for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
    for (const double damping : {0.0, 504.0}) {
      const bool sticking = model == FrictionModel::stick_slip;
      const OscillatorParams p = seat(model, damping, sticking ? 25.0 : 0.0, 30.0);
      History fixed_plain, double_plain, got;
      const auto run_all = [&](auto law) {
        using Law = decltype(law);
        Oscillator<Fixed, Law> plain;
        CHECK_TRUE(plain.configure(p).ok());
        fixed_plain = run_history(plain, a_u);
        Oscillator<double, Law> exact;
        CHECK_TRUE(exact.configure(p).ok());
        double_plain = run_history(exact, a_u);
        got = end_stop_history<Fixed, Law>(p, stops(10.0, 0.0), a_u);
      };
      if (sticking) {
        run_all(CoulombStickSlip{});
      } else {
        run_all(NoFriction{});
      }
      const Deviation spread = deviation(fixed_plain, double_plain, 20.0);
      const Deviation to_plain = deviation(got, fixed_plain, 20.0);
      const Deviation to_double = deviation(got, double_plain, 20.0);
      print(sticking ? "stick-slip: plain fixed vs double" : "frictionless: plain fixed vs double",
            spread);
      print("  with stops (fixed) vs plain fixed", to_plain);
      print("  with stops (fixed) vs double", to_double);
      if (sticking) CHECK(double_plain.stuck_s > 1.0);
      CHECK_EQUAL(0u, got.contacts);
      CHECK_EQUAL(0u, got.saturated);
      CHECK(to_double.x <= 2.5 * spread.x);
      CHECK(to_double.a_x <= 2.5 * spread.a_x);
      CHECK(to_double.t_ax <= std::max(2.5 * spread.t_ax, 1e-9));
      CHECK(to_double.p <= std::max(2.5 * spread.p, 1e-9));
      // Without friction there are no events to place: x_r is the plain one's bit for bit (a_x
      // is formed as (k x + b v)/m there, k/m x + b/m v in the plain oscillator).
      if (!sticking) CHECK(got.x == fixed_plain.x);
    }
  }
}

// In contact (stops at the RMS free stroke, 2e5 N/m, damped): T_ax and p against the double
// model within docs/EMBEDDED.md's fixed-point targets (T_ax 1 %, p 0.01) by far: measured T_ax
// 3e-8 and p 5e-9 at most, so both are held to 1e-6 here, with the same contacts, no saturation.
TEST(EndStopFixedPoint, ContactFollowsTheDoubleModelWithinTheFixedPointTargets) {
  const std::vector<double> a_u = wideband(2.0, 20.0, 13);
  for (const FrictionModel model : {FrictionModel::stick_slip, FrictionModel::linear}) {
    for (const double damping : {0.0, 504.0}) {
      const bool sticking = model == FrictionModel::stick_slip;
      const OscillatorParams p = seat(model, damping, sticking ? 25.0 : 0.0, 30.0);
      const EndStopParams s = stops(sticking ? rms_free_stroke<CoulombStickSlip>(p, a_u)
                                             : rms_free_stroke<NoFriction>(p, a_u),
                                    2.0e3);
      const History want = sticking ? end_stop_history<double, CoulombStickSlip>(p, s, a_u)
                                    : end_stop_history<double, NoFriction>(p, s, a_u);
      const History got = sticking ? end_stop_history<Fixed, CoulombStickSlip>(p, s, a_u)
                                   : end_stop_history<Fixed, NoFriction>(p, s, a_u);
      const Deviation d = deviation(got, want, 20.0);
      print(sticking ? (damping > 0 ? "contact, stick-slip, damped" : "contact, stick-slip")
                     : (damping > 0 ? "contact, frictionless, damped" : "contact, frictionless"),
            d);
      CHECK(want.contacts > 10);
      CHECK_EQUAL(want.contacts, got.contacts);
      CHECK_EQUAL(0u, got.saturated);
      CHECK_EQUAL(0u, got.budget_exhausted);
      CHECK_EQUAL(0u, got.resets);
      CHECK(d.t_ax <= 1e-6);
      CHECK(d.p <= 1e-6);
    }
  }
}

// A scene the format cannot hold in contact is refused by configure(), naming the stop's
// parameter: a stop of 1e7 N/m (which double takes: omega0 dt = 0.34 in contact) makes k + k_s
// beyond Q23.40's range with its headroom (2^21 = 2.1e6).
TEST(EndStopFixedPoint, ConfigureRefusesAStopTheFormatCannotHold) {
  const OscillatorParams p = seat(FrictionModel::stick_slip, 504.0, 25.0, 30.0);
  EndStopParams s = stops(0.05, 2.0e3);
  s.stiffness_n_per_m = 1e7;
  EndStopOscillator<double, CoulombStickSlip> in_double;
  CHECK_TRUE(in_double.configure(p, s).ok());
  EndStopOscillator<Fixed, CoulombStickSlip> model;
  const ConfigResult refused = model.configure(p, s);
  CHECK_FALSE(refused.ok());
  STRCMP_CONTAINS("end_stop_stiffness_n_per_m", refused.message.c_str());
  STRCMP_CONTAINS("Q23.40", refused.message.c_str());
}
