// The closed loop split over the loopback bus (stickslip plant + stickslip controller, the
// library calls behind them, in two threads): lock-step, it equals the in-process closed loop
// with the bus's resolutions bit for bit, trace and figures; with answers dropped or stopped it
// ends in the documented state with every missing answer counted, its trace equal to an oracle
// loop written here that applies the fault policy by hand; a bus that fails makes it passive.
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "stickslip/can/codec.hpp"
#include "stickslip/control/control_unit.hpp"
#include "stickslip/host/bus/control_nodes.hpp"
#include "stickslip/host/run/closed_loop.hpp"
#include "stickslip/host/signals/random.hpp"
#include "stickslip/models/dispatch.hpp"
#include "stickslip/port/transport.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

// A 3 s lorry-like floor at 1 kHz: many stick-slip cycles, a short test.
std::string lorry(const test::TempDir& dir) {
  const std::string input = dir.file("lorry.csv");
  const test::CliRun run =
      test::run_stickslip({"generate", "--kind", "lorry", "--rms", "0.6", "--duration", "3", "--dt",
                           "0.001", "--seed", "3", "--output", input});
  CHECK_EQUAL(0, run.status);
  return input;
}

// The seat of the other closed-loop tests, skyhook with a lagging actuator and noisy sensors:
// every part of the unit (estimator, hook law, lag) shapes the force.
ClosedLoopSetup skyhook_setup() {
  ClosedLoopSetup s;
  s.plant.params.model = FrictionModel::stick_slip;
  s.plant.params.integrator = default_integrator(FrictionModel::stick_slip);
  s.plant.params.kinetic_friction_n = 40.0;
  s.plant.params.static_friction_n = 55.0;
  s.plant.repetitions = 1;
  s.controller = ControllerChoice::skyhook;
  s.gain_ns_per_m = 1500.0;
  s.actuator_lag_s = 0.005;
  s.a_x_noise_m_per_s2 = 0.02;
  s.x_r_noise_m = 1e-4;
  s.seed = 7;
  return s;
}

struct Endpoints {
  std::unique_ptr<port::Transport> plant, controller;
};

Endpoints open_loopback() {
  Endpoints e{port::make_transport("loopback"), port::make_transport("loopback")};
  CHECK_TRUE(e.plant->open("loopback") == port::TransportStatus::ok);
  CHECK_TRUE(e.controller->open("loopback") == port::TransportStatus::ok);
  return e;
}

struct BusRun {
  PlantNodeResult plant;
  ControllerNodeResult controller;
};

// Plant in this thread, controller in another, both on the loopback bus.
BusRun run_over_bus(const ClosedLoopSetup& setup, const std::string& input,
                    const std::string& output, ControllerNodeRequest controller,
                    PlantNodeRequest plant = {}) {
  Endpoints bus = open_loopback();
  controller.setup = setup;
  controller.transport = bus.controller.get();
  controller.idle_exit_s = 0.5;
  BusRun run;
  std::thread node([&] { run.controller = run_controller_node(controller); });
  plant.input_path = input;
  plant.output_path = output;
  plant.setup = setup;
  plant.transport = bus.plant.get();
  try {
    run.plant = run_plant_node(plant);
  } catch (...) {
    node.join();
    throw;
  }
  node.join();
  return run;
}

}  // namespace

TEST_GROUP(ClosedLoopBus){};

// The lock-step loop over the bus against the in-process loop with the bus's resolutions: the
// trace byte for byte (the same doubles written the same way) and the figures (the same numbers
// in the same JSON text), every step with its answer. Returns the plant node's JSON line.
static nlohmann::json check_bus_loop_equals_in_process_loop(const ClosedLoopSetup& setup) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopRequest in_process;
  in_process.input_path = input;
  in_process.output_path = dir.file("in_process.csv");
  in_process.setup = setup;
  set_can_resolution(in_process.setup);
  const ClosedLoopResult reference = closed_loop_file(in_process);

  const BusRun bus = run_over_bus(setup, input, dir.file("bus.csv"), {});
  const std::string expected = test::read_text(in_process.output_path);
  CHECK_TRUE(expected.size() > 1000);
  CHECK_TRUE(expected == test::read_text(dir.file("bus.csv")));
  const nlohmann::json r = nlohmann::json::parse(reference.json),
                       p = nlohmann::json::parse(bus.plant.json);
  STRCMP_EQUAL(r["controlled"].dump().c_str(), p["controlled"].dump().c_str());
  // The force did act (the comparison is not between two passive runs).
  CHECK_TRUE(r["controlled"]["force_rms"].get<double>() > 1.0);
  // Every step had its answer: no hold, no fail-safe; the controller answered every sample.
  const std::uint64_t samples = r["samples"].get<std::uint64_t>();
  CHECK_EQUAL(samples - 1, bus.plant.counters.commands_applied);
  CHECK_EQUAL(0u, bus.plant.counters.commands_missing);
  CHECK_EQUAL(0u, bus.plant.counters.held_frames + bus.plant.counters.failsafe_frames);
  STRCMP_EQUAL("ok", bus.plant.state.c_str());
  CHECK_EQUAL(samples, bus.controller.answered);
  CHECK_EQUAL(0u, bus.controller.sample_gaps + bus.controller.corrupt_frames);
  return p;
}

TEST(ClosedLoopBus, LockStepLoopEqualsInProcessLoopWithBusResolutionBitForBit) {
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  check_bus_loop_equals_in_process_loop(setup);
}

// The plant node runs the scene's model as closed-loop does, end stops included: with stops at
// +-2 mm the controlled seat hits them (7 times), and the loop over the bus still equals the
// in-process loop bit for bit, the contact count included.
TEST(ClosedLoopBus, LockStepLoopWithEndStopsEqualsInProcessLoopBitForBit) {
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  setup.plant.effects |= kEndStops;
  setup.plant.params.integrator = Integrator::exact;  // the end-stop model's only one
  setup.plant.stops.travel_m = 0.002;
  const nlohmann::json plant = check_bus_loop_equals_in_process_loop(setup);
  CHECK_TRUE(plant["controlled"]["end_stop_contacts"].get<int>() > 5);
}

TEST(ClosedLoopBus, WithoutBusResolutionTheInProcessLoopDiffers) {
  // The control of the test above: the bus's quantisation is what the twin reproduces.
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopRequest in_process;
  in_process.input_path = input;
  in_process.output_path = dir.file("in_process.csv");
  in_process.setup = skyhook_setup();
  closed_loop_file(in_process);
  const BusRun bus = run_over_bus(skyhook_setup(), input, dir.file("bus.csv"), {});
  CHECK_FALSE(test::read_text(in_process.output_path) == test::read_text(dir.file("bus.csv")));
}

namespace {

// The oracle of a faulty run: the plant and the ControlUnit stepped here in one loop, the
// unit's answer to sample n reaching the plant unless `lost(n)`, and then the documented policy:
// the last force held for hold_frames answers, 0 after.
template <typename Lost>
std::vector<double> oracle_forces(const ClosedLoopSetup& given, const std::vector<double>& a_u,
                                  int hold_frames, Lost lost) {
  ClosedLoopSetup setup = given;
  set_can_resolution(setup);
  const ClosedLoopParams params = closed_loop_params(setup, setup.plant.params.dt_s);
  ControlUnit<double> unit;
  CHECK_TRUE(unit.configure(params).ok());
  LoopSensors<double> sensors;
  CHECK_TRUE(sensors.configure(params).ok());
  GaussianSource a_x_noise(setup.seed, 1), x_r_noise(setup.seed, 2);
  std::vector<double> f_a(a_u.size(), 0.0);
  with_oscillator<double>(setup.plant.params, [&](auto& seat) {
    CHECK_TRUE(seat.configure(setup.plant.params).ok());
    seat.reset(setup.plant.x0_m, setup.plant.v0_m_per_s, a_u[0]);
    unit.reset(a_u[0], setup.plant.x0_m);
    double last = 0.0, force = 0.0;
    int missing = 0;
    const auto policy = [&](std::size_t n, double answer) {
      if (!lost(n)) {
        missing = 0;
        last = answer;
        return answer;
      }
      if (missing < hold_frames) {
        ++missing;
        return last;
      }
      return 0.0;
    };
    force = policy(0, unit.force_n());
    for (std::size_t n = 1; n < a_u.size(); ++n) {
      f_a[n] = force;
      const StepOutput<double> out = seat.step(a_u[n], force);
      const double ax = sensors.a_x(out.a_x_m_per_s2, setup.a_x_noise_m_per_s2 * a_x_noise.next());
      const double xr = sensors.x_r(out.x_r_m, setup.x_r_noise_m * x_r_noise.next());
      const UnitSample<double> s = unit.step(a_u[n], ax, xr, unit.force_n());
      force = policy(n, s.next_force_n);
    }
  });
  return f_a;
}

}  // namespace

TEST(ClosedLoopBus, DroppedAnswersAreHeldAndCountedAndTheTraceFollowsThePolicy) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  ControllerNodeRequest controller;
  controller.drop_every = 97;
  PlantNodeRequest plant;
  plant.hold_frames = 3;
  // Long enough that a busy machine does not turn a slow answer into a missing one.
  plant.command_timeout_s = 0.2;
  const BusRun bus = run_over_bus(setup, input, dir.file("bus.csv"), controller, plant);
  const test::Table trace = test::read_table(dir.file("bus.csv"));
  const std::vector<double> a_u = test::column(trace, 1), f_a = test::column(trace, 7);
  const std::size_t samples = a_u.size();
  // Answers to samples 96, 193, ... are dropped; the plant needs those to samples 0..N-2.
  const auto lost = [](std::size_t n) { return (n + 1) % 97 == 0; };
  std::uint64_t expected_missing = 0;
  for (std::size_t n = 0; n + 1 < samples; ++n) expected_missing += lost(n) ? 1 : 0;
  CHECK_TRUE(expected_missing >= 20);
  CHECK_EQUAL(expected_missing, bus.plant.counters.commands_missing);
  CHECK_EQUAL(expected_missing, bus.plant.counters.held_frames);  // single losses: all held
  CHECK_EQUAL(0u, bus.plant.counters.failsafe_frames);
  CHECK_EQUAL(samples - 1 - expected_missing, bus.plant.counters.commands_applied);
  STRCMP_EQUAL("ok", bus.plant.state.c_str());
  CHECK_EQUAL(samples / 97, bus.controller.dropped);
  // The trace's force, sample for sample, is the oracle's (the CSV prints doubles round-trip).
  const std::vector<double> oracle = oracle_forces(setup, a_u, 3, lost);
  for (std::size_t n = 0; n < samples; ++n) CHECK_TRUE(test::bit_equal(oracle[n], f_a[n]));
}

TEST(ClosedLoopBus, AControllerThatStopsAnsweringLeavesThePlantFailingSafeEveryFrameCounted) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  ControllerNodeRequest controller;
  controller.stop_after_s = 2.0;  // answers to samples 0..1999, none from 2000 on
  PlantNodeRequest plant;
  plant.hold_frames = 5;
  plant.command_timeout_s = 0.2;
  const BusRun bus = run_over_bus(setup, input, dir.file("bus.csv"), controller, plant);
  const test::Table trace = test::read_table(dir.file("bus.csv"));
  const std::vector<double> a_u = test::column(trace, 1), f_a = test::column(trace, 7);
  const std::size_t samples = a_u.size();
  const std::uint64_t missing = samples - 1 - 2000;  // the steps from sample 2000 on
  CHECK_EQUAL(2000u, bus.plant.counters.commands_applied);
  CHECK_EQUAL(missing, bus.plant.counters.commands_missing);
  CHECK_EQUAL(5u, bus.plant.counters.held_frames);
  CHECK_EQUAL(missing - 5, bus.plant.counters.failsafe_frames);
  CHECK_EQUAL(2005u, bus.plant.counters.first_failsafe_sample);
  CHECK_EQUAL(2005u, bus.plant.counters.last_failsafe_sample);
  STRCMP_EQUAL("failsafe", bus.plant.state.c_str());
  CHECK_EQUAL(samples - 2000, bus.controller.silenced);
  const std::vector<double> oracle =
      oracle_forces(setup, a_u, 5, [](std::size_t n) { return n >= 2000; });
  for (std::size_t n = 0; n < samples; ++n) CHECK_TRUE(test::bit_equal(oracle[n], f_a[n]));
  // Passive from step 2005 -> 2006 on, while the held force was not 0.
  CHECK_TRUE(f_a[2005] != 0.0);
  for (std::size_t n = 2006; n < samples; ++n) CHECK_TRUE(f_a[n] == 0.0);
}

namespace {

// The loopback bus that fails (as SocketCAN's ENETDOWN) from the k-th send on.
class FailingTransport final : public port::Transport {
 public:
  FailingTransport(port::Transport& inner, std::uint64_t fail_from)
      : inner_(inner), fail_from_(fail_from) {}
  port::TransportStatus open(const std::string& name) noexcept override {
    return inner_.open(name);
  }
  port::TransportStatus set_filters(const port::ReceiveFilter* f, std::size_t n) noexcept override {
    return inner_.set_filters(f, n);
  }
  port::TransportStatus send(const can::Frame& frame) noexcept override {
    if (++sends_ >= fail_from_) return port::TransportStatus::interface_down;
    return inner_.send(frame);
  }
  port::TransportStatus receive(can::Frame& frame, int timeout_ms) noexcept override {
    return inner_.receive(frame, timeout_ms);
  }
  void close() noexcept override { inner_.close(); }
  port::TransportCounters counters() const noexcept override { return inner_.counters(); }

 private:
  port::Transport& inner_;
  std::uint64_t fail_from_, sends_ = 0;
};

}  // namespace

TEST(ClosedLoopBus, ABusThatGoesDownLeavesThePlantPassiveAndSaysSo) {
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  Endpoints bus = open_loopback();
  // Two frames per sample: the 2001st send is sample 1000's SeatSensors.
  FailingTransport failing(*bus.plant, 2001);
  ControllerNodeRequest controller;
  controller.setup = setup;
  controller.transport = bus.controller.get();
  controller.idle_exit_s = 0.5;
  ControllerNodeResult answered;
  std::thread node([&] { answered = run_controller_node(controller); });
  PlantNodeRequest plant;
  plant.input_path = input;
  plant.output_path = dir.file("bus.csv");
  plant.setup = setup;
  plant.transport = &failing;
  const PlantNodeResult result = run_plant_node(plant);
  node.join();
  const std::vector<double> f_a = test::column(test::read_table(dir.file("bus.csv")), 7);
  STRCMP_EQUAL("bus_down", result.state.c_str());
  CHECK_EQUAL(1000u, result.counters.bus_down_sample);
  CHECK_EQUAL(1000u, result.counters.commands_applied);  // answers to samples 0..999
  CHECK_EQUAL(f_a.size() - 1 - 1000, result.counters.bus_down_frames);
  CHECK_TRUE(result.bus_message.find("sample 1000 (interface down)") != std::string::npos);
  for (std::size_t n = 1001; n < f_a.size(); ++n) CHECK_TRUE(f_a[n] == 0.0);
  CHECK_EQUAL(1000u, answered.answered);
}

TEST(ClosedLoopBus, RealTimePacingReportsEveryTickAndAccountsForEveryStep) {
  // Timing itself depends on the machine (docs/CONTROL.md quotes the vcan guest's); what holds
  // everywhere: one lateness per tick, ordered statistics, and every step's answer applied or
  // counted missing.
  test::TempDir dir;
  const std::string input = lorry(dir);
  ClosedLoopSetup setup = skyhook_setup();
  setup.plant.params.dt_s = 1e-3;
  PlantNodeRequest plant;
  plant.pace = Pace::realtime;
  const BusRun bus = run_over_bus(setup, input, dir.file("rt.csv"), {}, plant);
  const std::uint64_t steps = test::read_table(dir.file("rt.csv")).rows.size() - 1;
  CHECK_EQUAL(steps, bus.plant.pacing.ticks);
  CHECK_TRUE(bus.plant.pacing.lateness_median_s >= 0.0);
  CHECK_TRUE(bus.plant.pacing.lateness_median_s <= bus.plant.pacing.lateness_p999_s);
  CHECK_TRUE(bus.plant.pacing.lateness_p999_s <= bus.plant.pacing.lateness_worst_s);
  CHECK_TRUE(bus.plant.pacing.deadline_misses <= steps);
  CHECK_EQUAL(steps, bus.plant.counters.commands_applied + bus.plant.counters.commands_missing);
  CHECK_EQUAL(bus.plant.counters.commands_missing,
              bus.plant.counters.held_frames + bus.plant.counters.failsafe_frames);
  const nlohmann::json json = nlohmann::json::parse(bus.plant.json);
  STRCMP_EQUAL("realtime", json["pace"].get<std::string>().c_str());
  CHECK_EQUAL(steps, json["pacing"]["ticks"].get<std::uint64_t>());
}

TEST(ClosedLoopBus, PlantAndControllerRefuseWhatTheBusCannotDoInOneLine) {
  const auto refused = [](const std::vector<std::string>& arguments, const char* why) {
    const test::CliRun run = test::run_stickslip(arguments);
    CHECK_EQUAL(2, run.status);
    CHECK_EQUAL(1u, test::split_lines(run.err).size());
    STRCMP_CONTAINS(why, run.err.c_str());
    CHECK_TRUE(run.out.empty());
  };
  refused({"controller", "--bus", "vcan0", "--model", "stick-slip", "--observer", "ideal"},
          "--observer ideal: over a bus the controller has only the frames' sensors");
  refused({"controller", "--bus", "vcan0", "--model", "stick-slip", "--force-limit", "3000"},
          "--force-limit 3000: the ActuatorCommand frame carries at most 2047.9375 N");
  refused({"controller", "--bus", "loopback", "--model", "stick-slip"},
          "--bus loopback: controller would wait forever");
  refused({"plant", "--bus", "loopback", "--input", "in.csv", "--output", "out.csv", "--model",
           "stick-slip"},
          "--bus loopback: plant would wait forever");
  refused({"plant", "--bus", "vcan0", "--input", "in.csv", "--output", "out.csv", "--model",
           "stick-slip", "--pace", "fast"},
          "--pace fast: expected max or realtime");
}
