// The closed loop run in process (run/closed_loop.hpp over control/closed_loop.hpp): the
// one-frame delay of the force, the semi-active damper never pushing, the user's controller.
#include <cmath>
#include <cstddef>
#include <vector>

#include "stickslip/host/run/closed_loop.hpp"
#include "stickslip/host/signals/random.hpp"
#include "support/host_test_support.hpp"

// CppUTest last: its leak detector redefines new.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

// A band-limited random floor (first-order low-pass of white noise at about 3 Hz), 10 s at 1 kHz:
// enough motion for stick and slip phases.
std::vector<double> floor_input() {
  GaussianSource noise(11);
  std::vector<double> a_u(10001);
  double state = 0.0;
  const double alpha = 1.0 - std::exp(-2.0 * 3.14159265358979 * 3.0 * 1e-3);
  for (double& a : a_u) {
    state += alpha * (8.0 * noise.next() - state);
    a = state;
  }
  return a_u;
}

ClosedLoopSetup stick_slip_seat() {
  ClosedLoopSetup setup;
  setup.plant.params.model = FrictionModel::stick_slip;
  setup.plant.params.kinetic_friction_n = 40.0;
  setup.plant.params.static_friction_n = 55.0;
  setup.plant.params.dt_s = 1e-3;
  setup.a_x_noise_m_per_s2 = 0.02;
  setup.x_r_noise_m = 3e-5;
  setup.seed = 5;
  return setup;
}

}  // namespace

TEST_GROUP(ClosedLoopRun){};

// The force the loop computes at sample n acts on the step into sample n + 1, never earlier: with
// an ideal actuator (no lag, a limit it never reaches) f_a[n + 1] is the command of sample n.
TEST(ClosedLoopRun, ForceComputedAtOneSampleActsOverTheNextStep) {
  ClosedLoopSetup setup = stick_slip_seat();
  setup.controller = ControllerChoice::skyhook;
  setup.force_limit_n = 1e9;
  ClosedLoopTrace trace;
  const std::vector<double> a_u = floor_input();
  run_closed_loop(setup, a_u, trace);
  CHECK_TRUE(test::bit_equal(0.0, trace.f_a_n[0]));
  CHECK_TRUE(test::bit_equal(0.0, trace.f_a_n[1]));  // nothing computed before sample 1
  std::size_t nonzero = 0;
  for (std::size_t n = 1; n + 1 < a_u.size(); ++n) {
    CHECK_TRUE(test::bit_equal(trace.command_n[n], trace.f_a_n[n + 1]));
    if (trace.command_n[n] != 0.0) ++nonzero;
  }
  CHECK_TRUE(nonzero > a_u.size() / 2);
}

// The semi-active damper's command is always dissipative for the v_r the controller read:
// command * v_r <= 0 at every sample; the active skyhook on the same run is not (it pushes).
TEST(ClosedLoopRun, SemiActiveCommandNeverFeedsEnergyIn) {
  const std::vector<double> a_u = floor_input();
  for (const ControllerChoice choice :
       {ControllerChoice::skyhook_semi, ControllerChoice::groundhook_semi}) {
    ClosedLoopSetup setup = stick_slip_seat();
    setup.controller = choice;
    setup.actuator_lag_s = 0.004;
    ClosedLoopTrace trace;
    const ControlFigures figures = run_closed_loop(setup, a_u, trace);
    std::size_t pushing = 0, acting = 0;
    for (std::size_t n = 1; n < a_u.size(); ++n) {
      if (trace.command_n[n] * trace.sensed_v_r_m_per_s[n] > 0.0) ++pushing;
      if (trace.command_n[n] != 0.0) ++acting;
    }
    CHECK_EQUAL(0u, pushing);
    CHECK_TRUE(acting > a_u.size() / 4);
    // (Not a bound the delay and the lag guarantee sample by sample, but over a run a damper
    // takes energy out.)
    CHECK_TRUE(figures.mean_power_w < 0.0);
  }
  ClosedLoopSetup setup = stick_slip_seat();
  setup.controller = ControllerChoice::skyhook;
  ClosedLoopTrace trace;
  run_closed_loop(setup, a_u, trace);
  std::size_t pushing = 0;
  for (std::size_t n = 1; n < a_u.size(); ++n)
    if (trace.command_n[n] * trace.sensed_v_r_m_per_s[n] > 0.0) ++pushing;
  CHECK_TRUE(pushing > 0);
}

// The user's controller in the loop: a plain damper -c v_r as a captureless lambda gives the
// same run as the semi-active damper with b_min = b_max = c (whose clipped law is then exactly
// -c v_r whatever the desired force).
TEST(ClosedLoopRun, UserDamperEqualsSemiActiveWithFixedDamping) {
  const std::vector<double> a_u = floor_input();
  ClosedLoopSetup setup = stick_slip_seat();
  setup.controller = ControllerChoice::skyhook_semi;
  setup.min_damping_ns_per_m = setup.max_damping_ns_per_m = 700.0;
  ClosedLoopTrace semi, user;
  run_closed_loop(setup, a_u, semi);
  const UserController<double> damper{
      [](const SensorSample<double>& s, void*) { return -(700.0 * s.v_r_m_per_s); }};
  setup.user = &damper;
  run_closed_loop(setup, a_u, user);
  for (std::size_t n = 0; n < a_u.size(); ++n) {
    CHECK_TRUE(test::bit_equal(semi.f_a_n[n], user.f_a_n[n]));
    CHECK_TRUE(test::bit_equal(semi.plant.a_x_m_per_s2[n], user.plant.a_x_m_per_s2[n]));
  }
}

// The observer is told the force that acted: its friction estimate is the seat's F_f, not
// F_f - f_a. With the friction fed forward (f = 0.8 F_f estimate) an observer blind to the force
// would settle at F_f / 1.8, 44 % below; told it, the command follows 0.8 F_f of the plant.
TEST(ClosedLoopRun, FrictionFeedForwardFollowsTheSeatsFrictionNotItsOwnForce) {
  const std::vector<double> a_u = floor_input();
  ClosedLoopSetup setup = stick_slip_seat();
  setup.controller = ControllerChoice::friction_compensation;
  setup.friction_compensation = 0.8;
  ClosedLoopTrace trace;
  run_closed_loop(setup, a_u, trace);
  double error2 = 0.0, friction2 = 0.0;
  std::size_t slipping = 0;
  for (std::size_t n = 100; n < a_u.size(); ++n) {
    // Slipping for the last 10 steps: the estimator's transient after an event has passed.
    bool slip = true;
    for (std::size_t k = 0; k < 10; ++k) slip = slip && trace.plant.stuck[n - k] == 0;
    if (!slip) continue;
    const double expected = 0.8 * trace.plant.friction_n[n];
    error2 += (trace.command_n[n] - expected) * (trace.command_n[n] - expected);
    friction2 += expected * expected;
    ++slipping;
  }
  CHECK_TRUE(slipping > a_u.size() / 4);
  const double relative = std::sqrt(error2 / friction2);
  // 0.019 here (the estimator's error under the sensors' noise and the force's steps between its
  // first-order-hold samples); an observer blind to the force is off by 0.44.
  CHECK_TRUE(relative < 0.05);
}
