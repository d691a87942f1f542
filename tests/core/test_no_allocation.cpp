// The core never touches the heap: configure(), reset(), step() of every law in float and double
// (event paths included), the run-time dispatch and the statistics make zero allocations.
// The counter interposes malloc; AllocationCounter proves it sees real allocations.
#include <cfenv>
#include <cstddef>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "oracles.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/dispatch.hpp"
#include "support/allocation_counter.hpp"

using namespace stickslip;

namespace {

constexpr std::size_t kSteps = 20000;  // 20 s at 1 ms: many stick, break-away and reversal events

// Lorry-like input at K ~ 1: sticks about half the time, so every event path runs. Built by each
// test before counting starts (and freed by it: CppUTest checks for leaks).
template <typename T>
std::vector<T> lorry_input() {
  const std::vector<double> input = test::make_lorry_signal(3, 0.35).sample(1e-3, kSteps + 1);
  return std::vector<T>(input.begin(), input.end());
}

OscillatorParams scene(FrictionModel model, SmoothingLaw smoothing, Integrator integrator) {
  OscillatorParams p = test::reference_params(model, integrator, 1e-3);
  p.kinetic_friction_n = 35.0;
  p.static_friction_n = 45.0;
  p.smoothing = smoothing;
  return p;
}

struct Activity {
  std::size_t allocations;
  int events;
  int stuck_steps;
  bool configured;
};

// Everything between start and stop is the per-scene work of a real run.
template <typename T, typename Law>
Activity run_counted(const OscillatorParams& params, const std::vector<T>& input) {
  Oscillator<T, Law> seat;
  RunningStatistics<T> stats;
  int events = 0, stuck_steps = 0;
  test::start_counting_allocations();
  const bool configured = seat.configure(params).ok();
  seat.reset(T(0), T(0), input[0]);
  stats.reset();
  stats.add_sample(input[0], seat.current().a_x_m_per_s2);
  for (std::size_t n = 1; n < input.size(); ++n) {
    const auto out = seat.step(input[n]);
    stats.add_sample(input[n], out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    events += out.events;
    stuck_steps += out.stuck ? 1 : 0;
  }
  volatile double sink = stats.transmissibility() + stats.stick_probability() + stats.rms_u();
  (void)sink;
  const auto seen = test::stop_counting_allocations();
  // Underflow of the float Stribeck law at break-away is judged by
  // StickSlip.FloatStribeckBreakAwayRaisesNoUnderflow. Cleared so that this test judges
  // allocations only.
  if (sizeof(T) == sizeof(float) && Law::model == FrictionModel::stribeck)
    std::feclearexcept(FE_UNDERFLOW);
  return {seen.calls, events, stuck_steps, configured};
}

template <typename T>
void check_every_law() {
  const std::vector<T> input = lorry_input<T>();
  const Integrator integrators[] = {Integrator::euler, Integrator::symplectic, Integrator::rk4,
                                    Integrator::exact};
  for (Integrator integrator : integrators) {
    const char* name = integrator_name(integrator);
    Activity a = run_counted<T, NoFriction>(
        scene(FrictionModel::linear, SmoothingLaw::tanh, integrator), input);
    CHECK_TEXT(a.configured, name);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    a = run_counted<T, SignumFriction>(scene(FrictionModel::signum, SmoothingLaw::tanh, integrator),
                                       input);
    CHECK_TEXT(a.configured, name);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    if (integrator == Integrator::exact) CHECK(a.events > 0);  // sign changes located
    a = run_counted<T, SmoothFriction<SmoothingLaw::atan>>(
        scene(FrictionModel::smooth, SmoothingLaw::atan, integrator), input);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    a = run_counted<T, SmoothFriction<SmoothingLaw::tanh>>(
        scene(FrictionModel::smooth, SmoothingLaw::tanh, integrator), input);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    a = run_counted<T, SmoothFriction<SmoothingLaw::erf>>(
        scene(FrictionModel::smooth, SmoothingLaw::erf, integrator), input);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    a = run_counted<T, SmoothFriction<SmoothingLaw::rational>>(
        scene(FrictionModel::smooth, SmoothingLaw::rational, integrator), input);
    CHECK_TEXT(a.configured, name);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    a = run_counted<T, CoulombStickSlip>(
        scene(FrictionModel::stick_slip, SmoothingLaw::tanh, integrator), input);
    CHECK_TEXT(a.configured, name);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    CHECK(a.events > 100 && a.stuck_steps > 1000);  // stick and slip both exercised
    a = run_counted<T, StribeckStickSlip>(
        scene(FrictionModel::stribeck, SmoothingLaw::tanh, integrator), input);
    CHECK_TEXT(a.configured, name);
    UNSIGNED_LONGS_EQUAL_TEXT(0, a.allocations, name);
    CHECK(a.events > 100 && a.stuck_steps > 1000);
  }
}

}  // namespace

TEST_GROUP(NoAllocation){};

TEST(NoAllocation, EveryLawInDoubleRunsWithoutHeap) {
  check_every_law<double>();
}

TEST(NoAllocation, EveryLawInFloatRunsWithoutHeap) {
  check_every_law<float>();
}

// The run-time dispatch resolves the law and runs it without the heap (no std::function, no new).
TEST(NoAllocation, DispatchAllocatesNothing) {
  const std::vector<double> input = lorry_input<double>();
  const FrictionModel models[] = {FrictionModel::linear, FrictionModel::signum,
                                  FrictionModel::smooth, FrictionModel::stick_slip,
                                  FrictionModel::stribeck};
  for (FrictionModel model : models) {
    const OscillatorParams p = scene(model, SmoothingLaw::erf, Integrator::exact);
    test::start_counting_allocations();
    const double last_x = with_oscillator<double>(p, [&](auto& seat) {
      if (!seat.configure(p).ok()) return -1.0;
      seat.reset(0.0, 0.0, input[0]);
      double x = 0.0;
      for (std::size_t n = 1; n < 2000; ++n) x = seat.step(input[n]).x_r_m;
      return x;
    });
    const auto seen = test::stop_counting_allocations();
    UNSIGNED_LONGS_EQUAL_TEXT(0, seen.calls, model_name(model));
    CHECK(last_x != -1.0);
  }
}

// Refusals build their message in a fixed buffer, numbers included: no heap on the error path.
TEST(NoAllocation, RefusedConfigurationAndDenHartogAllocateNothing) {
  OscillatorParams p = scene(FrictionModel::smooth, SmoothingLaw::tanh, Integrator::euler);
  p.smoothing_constant_s_per_m = 1e6;  // unstable: the message formats numbers
  Oscillator<double, SmoothFriction<SmoothingLaw::tanh>> seat;
  test::start_counting_allocations();
  const auto config = seat.configure(p);
  volatile double k = den_hartog_factor(35.0, test::kMassKg, 0.35);
  const FrictionRegime regime = friction_regime(k);
  const auto seen = test::stop_counting_allocations();
  UNSIGNED_LONGS_EQUAL(0, seen.calls);
  CHECK_FALSE(config.ok());
  CHECK(regime == FrictionRegime::stick_slip_required);
}
