// The reference controllers (lib/include/stickslip/control) against closed forms: the actuator's
// first-order lag step response and its force limit, the leaky integrator's response to a
// constant acceleration, the semi-active law's dissipation (f v_r <= 0 and b_min |v_r| <= |f| <=
// b_max |v_r| for every sample), the active hooks' forces, the friction feed-forward and the user
// hook.
#include <algorithm>
#include <cmath>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/control/absolute_velocity.hpp"
#include "stickslip/control/actuator.hpp"
#include "stickslip/control/friction_compensation.hpp"
#include "stickslip/control/hook_damping.hpp"
#include "stickslip/control/user_controller.hpp"
#include "stickslip/core/fixed_point.hpp"

using namespace stickslip;

namespace {

SensorSample<double> sample(double v_seat, double v_floor) {
  return {0.0, 0.0, 0.0, v_seat - v_floor, v_seat, v_floor, 0.0};
}

}  // namespace

TEST_GROUP(Control){};

// f[n] = U (1 - e^{-n dt/tau}) for a command U held from rest: the lag is exact under the hold.
TEST(Control, ActuatorLagFollowsTheFirstOrderStepResponse) {
  Actuator<double> actuator;
  CHECK(actuator.configure({1e-3, 1000.0, 0.02}).ok());
  double worst = 0.0;
  for (int n = 1; n <= 200; ++n) {
    const double f = actuator.step(300.0);
    const double exact = 300.0 * -std::expm1(-n * 1e-3 / 0.02);
    worst = std::fmax(worst, std::fabs(f - exact));
  }
  CHECK(worst < 1e-12 * 300.0);  // rounding of 200 recurrences
}

TEST(Control, ActuatorNeverExceedsItsLimitAndReachesIt) {
  for (double tau : {0.0, 0.005}) {
    Actuator<double> actuator;
    CHECK(actuator.configure({1e-3, 250.0, tau}).ok());
    double f = 0.0;
    for (int n = 0; n < 2000; ++n) {
      f = actuator.step(n % 400 < 200 ? 900.0 : -900.0);
      CHECK(std::fabs(f) <= 250.0);
    }
    DOUBLES_EQUAL(-250.0, f, tau == 0.0 ? 0.0 : 250.0 * std::exp(-0.2 / tau) * 2.0 + 1e-12);
  }
  Actuator<double> actuator;
  CHECK(actuator.configure({1e-3, 250.0, 0.0}).ok());
  CHECK_EQUAL(0.0, actuator.step(std::nan("")));  // fail safe: no force
  CHECK_FALSE(actuator.configure({1e-3, 0.0, 0.0}).ok());
  CHECK_FALSE(actuator.configure({1e-3, 100.0, -1.0}).ok());
}

// The same lag in Q23.40: the fixed-point recurrence stays within the format's resolution of the
// double one.
TEST(Control, ActuatorInFixedPointTracksTheDoubleOne) {
  Actuator<double> reference;
  Actuator<Fixed> fixed;
  CHECK(reference.configure({1e-3, 800.0, 0.01}).ok());
  CHECK(fixed.configure({1e-3, 800.0, 0.01}).ok());
  for (int n = 0; n < 500; ++n) {
    const double u = 1000.0 * std::sin(0.05 * n);
    DOUBLES_EQUAL(reference.step(u), fixed.step(Fixed(u)).to_double(), 1e-8);
  }
}

// v[n] = a tau (1 - e^{-n dt/tau}) under a constant acceleration.
TEST(Control, AbsoluteVelocityIsTheLeakyIntegralOfTheAcceleration) {
  AbsoluteVelocity<double> velocity;
  CHECK(velocity.configure({1e-3, 2.0}).ok());
  double worst = 0.0;
  for (int n = 1; n <= 3000; ++n) {
    const double v = velocity.step(0.5);
    worst = std::fmax(worst, std::fabs(v - 0.5 * 2.0 * -std::expm1(-n * 1e-3 / 2.0)));
  }
  CHECK(worst < 1e-12);
}

// For any velocities: the semi-active force dissipates and stays within the damper's range; it
// equals the skyhook force when that is reachable.
TEST(Control, SemiActiveForceIsAlwaysDissipativeAndWithinTheDamperRange) {
  for (HookReference reference : {HookReference::sky, HookReference::ground}) {
    HookController<double> hook;
    HookParams p;
    p.reference = reference;
    p.device = HookDevice::semi_active;
    p.gain_ns_per_m = 2000.0;
    p.min_damping_ns_per_m = 100.0;
    p.max_damping_ns_per_m = 2500.0;
    CHECK(hook.configure(p).ok());
    test::SplitMix64 random(17);
    int clipped = 0, exact = 0;
    for (int n = 0; n < 20000; ++n) {
      const SensorSample<double> s = sample(random.uniform(-0.5, 0.5), random.uniform(-0.5, 0.5));
      const double f = hook.step(s), v = s.v_r_m_per_s;
      CHECK(f * v <= 0.0);
      CHECK(std::fabs(f) <= 2500.0 * std::fabs(v) * (1 + 1e-15));
      CHECK(std::fabs(f) >= 100.0 * std::fabs(v) * (1 - 1e-15));
      const double desired =
          reference == HookReference::sky ? -2000.0 * s.v_seat_m_per_s : 2000.0 * s.v_floor_m_per_s;
      if (desired * v <= 0.0 && std::fabs(desired) >= 100.0 * std::fabs(v) &&
          std::fabs(desired) <= 2500.0 * std::fabs(v)) {
        CHECK_EQUAL(desired, f);
        ++exact;
      } else {
        ++clipped;
      }
    }
    CHECK(exact > 1000 && clipped > 1000);  // both branches ran
  }
}

// The hooks in float and Q23.40 give the double law's force on the same (rounded) velocities, to
// the one rounding of the product that picks the force: the clipped law is continuous, so a
// branch taken differently at a boundary moves the force by no more than that rounding either.
// And each format keeps the device dissipative exactly (f v_r <= 0 in the format's arithmetic).
template <typename T>
void check_hooks_in(double relative, double absolute) {
  using S = ScalarTraits<T>;
  for (HookReference reference : {HookReference::sky, HookReference::ground}) {
    for (HookDevice device : {HookDevice::active, HookDevice::semi_active}) {
      HookParams p;
      p.reference = reference;
      p.device = device;
      p.gain_ns_per_m = 2000.0;
      p.min_damping_ns_per_m = 100.0;
      p.max_damping_ns_per_m = 2500.0;
      HookController<T> hook;
      HookController<double> exact;
      CHECK(hook.configure(p).ok());
      CHECK(exact.configure(p).ok());
      test::SplitMix64 random(29);
      for (int n = 0; n < 20000; ++n) {
        const T v_seat = S::from_double(random.uniform(-0.5, 0.5));
        const T v_floor = S::from_double(random.uniform(-0.5, 0.5));
        const SensorSample<T> s{T(0), T(0), T(0), v_seat - v_floor, v_seat, v_floor, T(0)};
        const SensorSample<double> d{
            0.0, 0.0, 0.0, S::to_double(s.v_r_m_per_s), S::to_double(v_seat), S::to_double(v_floor),
            0.0};
        const T f = hook.step(s);
        const double scale =
            std::max({2000.0 * std::fabs(d.v_seat_m_per_s), 2000.0 * std::fabs(d.v_floor_m_per_s),
                      2500.0 * std::fabs(d.v_r_m_per_s)});
        DOUBLES_EQUAL(exact.step(d), S::to_double(f), relative * scale + absolute);
        if (device == HookDevice::semi_active) CHECK(f * s.v_r_m_per_s <= T(0));
      }
    }
  }
}

TEST(Control, HooksInFloatAndFixedPointGiveTheDoubleLawsForce) {
  check_hooks_in<float>(0x1p-24, 0.0);  // one rounding to float's 24 bits
  check_hooks_in<Fixed>(0.0, 0x1p-40);  // one rounding to Q23.40's last bit
}

TEST(Control, ActiveHooksGiveTheirDamperForce) {
  HookController<double> sky, ground;
  HookParams p;
  p.device = HookDevice::active;
  p.gain_ns_per_m = 1200.0;
  CHECK(sky.configure(p).ok());
  p.reference = HookReference::ground;
  CHECK(ground.configure(p).ok());
  CHECK_EQUAL(-1200.0 * 0.3, sky.step(sample(0.3, -0.1)));
  CHECK_EQUAL(1200.0 * -0.1, ground.step(sample(0.3, -0.1)));
  p.max_damping_ns_per_m = -1.0;
  CHECK_FALSE(sky.configure(p).ok());
}

TEST(Control, FrictionCompensationFeedsForwardTheEstimate) {
  FrictionCompensation<double> compensation;
  CHECK(compensation.configure({0.75}).ok());
  SensorSample<double> s = sample(0.0, 0.0);
  s.friction_estimate_n = -40.0;
  CHECK_EQUAL(-30.0, compensation.step(s));
  CHECK_FALSE(compensation.configure({1.5}).ok());
}

TEST(Control, AUserControllerIsOneLine) {
  UserController<double> c{
      [](const SensorSample<double>& s, void*) { return -900.0 * s.v_r_m_per_s; }};
  CHECK_EQUAL(-450.0, c.step(sample(0.75, 0.25)));
  UserController<double> none;
  CHECK_EQUAL(0.0, none.step(sample(0.3, 0.1)));
}
