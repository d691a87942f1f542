// The ECU node's state estimator (ecu --estimator) over the loopback bus: fed a reference-solver
// rig run (a_u in SeatInput, measured a_x and travel in SeatSensors), the estimates it publishes
// are, raw word for raw word, those of a StateEstimator run in this process on the decoded
// samples; without sensor frames it says what it cannot estimate. And the SeatSensors receive
// check (lib/can/sensor_receiver.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/sensor_receiver.hpp"
#include "stickslip/host/bus/bus_commands.hpp"
#include "stickslip/observer/state_estimator.hpp"
#include "stickslip/port/loopback_transport.hpp"
#include "support/cli_run.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using stickslip::test::run_stickslip;

namespace {

struct RigSample {
  double a_u, a_x, x_r;
};

// simulate's CSV (t,a_u,x_r,v_r,a_x,f_f,stuck) as the rig's true a_u, a_x and x_r.
std::vector<RigSample> read_rig(const std::string& path) {
  std::vector<RigSample> rows;
  std::FILE* file = std::fopen(path.c_str(), "r");
  char header[256];
  if (file == nullptr || std::fgets(header, sizeof header, file) == nullptr) return rows;
  double t, a_u, x_r, v_r, a_x, f_f, stuck;
  while (std::fscanf(file, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &a_u, &x_r, &v_r, &a_x, &f_f,
                     &stuck) == 7)
    rows.push_back({a_u, a_x, x_r});
  std::fclose(file);
  return rows;
}

// The node's seat (--mass 88.4 --stiffness 11500 --damping 504 --ffk 45: the estimates start at
// 45 N, the rig's friction is 60/70 N) as the estimator takes it, written out here rather than
// taken from the node's node_estimator_params().
StateEstimatorParams oracle_params() {
  StateEstimatorParams p;
  p.mass_kg = 88.4;
  p.stiffness_n_per_m = 11500.0;
  p.damping_ns_per_m = 504.0;
  p.initial_kinetic_friction_n = 45.0;
  p.initial_static_friction_n = 45.0;
  p.dt_s = 1e-3;
  return p;
}

host::EcuRequest node_request() {
  host::EcuRequest request;
  request.bus = "loopback";
  request.setup.params.model = FrictionModel::stick_slip;
  request.setup.params.integrator = Integrator::exact;
  request.setup.params.kinetic_friction_n = request.setup.params.static_friction_n = 45.0;
  request.estimator = true;
  return request;
}

struct Answers {
  std::vector<can::Frame> estimate, force, friction;
};

// Sends sample n's frames (sensors first, when given) and waits for the node's estimate frames
// of it: SeatEstimate and SeatEstimateForce, and FrictionEstimate every 10th sample.
void exchange(port::Transport& tester, const can::Frame* sensors, const can::Frame& input,
              std::uint64_t n, Answers& answers) {
  if (sensors != nullptr) CHECK(tester.send(*sensors) == port::TransportStatus::ok);
  CHECK(tester.send(input) == port::TransportStatus::ok);
  const int expected = n % 10 == 0 ? 3 : 2;
  for (int k = 0; k < expected; ++k) {
    can::Frame frame;
    if (tester.receive(frame, 2000) != port::TransportStatus::ok) {
      FAIL("the node did not answer");
      return;
    }
    if (frame.id == can::kSeatEstimate.id) answers.estimate.push_back(frame);
    if (frame.id == can::kSeatEstimateForce.id) answers.force.push_back(frame);
    if (frame.id == can::kFrictionEstimate.id) answers.friction.push_back(frame);
  }
}

std::unique_ptr<port::Transport> estimate_listener() {
  auto tester = port::make_loopback_transport();
  CHECK(tester->open("loopback") == port::TransportStatus::ok);
  static const port::ReceiveFilter filters[] = {{can::kSeatEstimate.id, can::kStandardIdMask},
                                                {can::kSeatEstimateForce.id, can::kStandardIdMask},
                                                {can::kFrictionEstimate.id, can::kStandardIdMask}};
  tester->set_filters(filters, 3);
  return tester;
}

void wait_for_node() {
  for (int wait = 0; wait < 2000 && port::loopback_endpoints() < 2; ++wait)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  LONGS_EQUAL(2, port::loopback_endpoints());
}

std::uint16_t word(const can::MessageSpec& message, double value) {
  return can::quantise(message.signals[0], value).word;  // signal 0's scale
}
std::uint16_t word1(const can::MessageSpec& message, double value) {
  return can::quantise(message.signals[1], value).word;
}

}  // namespace

TEST_GROUP(EcuEstimator) {
  stickslip::test::TempDir dir;
};

namespace {

// A reference-solver rig run (event-located, not the core's step) on a lorry input, with a
// friction the node's start values (45 N) do not know, and the sensors: accelerometer noise
// 0.02 m/s^2 and bias, travel noise, 0.1 mm resolution.
std::vector<RigSample> measured_rig(stickslip::test::TempDir& dir) {
  const std::string floor = dir.file("floor.csv"), rig = dir.file("rig.csv");
  LONGS_EQUAL(0, run_stickslip({"generate", "--kind", "lorry", "--rms", "1", "--duration", "30",
                                "--dt", "0.001", "--seed", "7", "--output", floor})
                     .status);
  LONGS_EQUAL(0, run_stickslip(
                     {"simulate",   "--input",       floor,       "--output", rig,    "--model",
                      "stick-slip", "--integrator",  "reference", "--mass",   "88.4", "--stiffness",
                      "11500",      "--damping",     "504",       "--ffk",    "60",   "--ffs",
                      "70",         "--repetitions", "1"})
                     .status);
  const std::vector<RigSample> truth = read_rig(rig);
  LONGS_EQUAL(30001, truth.size());
  std::mt19937_64 random(11);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<RigSample> measured(truth.size());
  for (std::size_t n = 0; n < truth.size(); ++n) {
    measured[n].a_u = truth[n].a_u + 0.02 * unit(random);
    measured[n].a_x = truth[n].a_x + 0.01 + 0.02 * unit(random);
    measured[n].x_r = std::round((truth[n].x_r + 3e-5 * unit(random)) / 1e-4) * 1e-4;
  }
  return measured;
}

// The node on the loopback bus in lock step: per sample SeatSensors, then SeatInput.
Answers run_node(const std::vector<RigSample>& measured, host::ScalarType scalar,
                 host::EcuResult& result) {
  host::EcuRequest request = node_request();
  request.scalar = scalar;
  request.max_frames = 2 * measured.size();
  auto tester = estimate_listener();
  std::thread ecu([&] { result = host::run_ecu(request); });
  wait_for_node();
  Answers answers;
  for (std::uint64_t n = 0; n < measured.size(); ++n) {
    const can::Frame sensors = can::make_sensor_frame(measured[n].a_x, measured[n].x_r, n);
    exchange(*tester, &sensors, can::make_input_frame(measured[n].a_u, n), n, answers);
  }
  ecu.join();
  LONGS_EQUAL(measured.size(), answers.estimate.size());
  LONGS_EQUAL(measured.size(), answers.force.size());
  LONGS_EQUAL(measured.size() / 10 + 1, answers.friction.size());
  return answers;
}

struct Comparison {
  std::uint64_t mismatches = 0, kinetic_published = 0, static_published = 0;
  double final_kinetic_n = 0.0;
};

// The oracle: the estimator in scalar T in this process on the samples as the node decodes them;
// every raw word the node published against the oracle's estimate quantised by the codec.
template <typename T>
Comparison compare_with_oracle(const std::vector<RigSample>& measured, const Answers& answers) {
  StateEstimator<T> oracle;
  const StateEstimatorParams params = oracle_params();
  CHECK_TRUE(oracle.configure(params).ok());
  // Published once the start value's weight is below e^-3: 3 averaging times of slip samples,
  // and ceil(3 / -ln(1 - w)) break-aways.
  const double kinetic_needed = 3.0 * params.kinetic_friction_time_s / params.dt_s;
  const double static_needed = std::ceil(3.0 / -std::log1p(-params.static_friction_weight));
  Comparison c;
  for (std::size_t n = 0; n < measured.size(); ++n) {
    const T a_u = T(can::quantised_input(measured[n].a_u));
    const T a_x = T(can::quantised_sensor(0, measured[n].a_x));
    const T x_r = T(can::quantised_sensor(1, measured[n].x_r));
    if (n == 0) {
      oracle.reset(a_u, x_r);
    } else {
      oracle.step(a_u, a_x, x_r);
    }
    const StateEstimate<T>& e = oracle.estimate();
    const can::Payload est = can::decode_payload(answers.estimate[n].data);
    const can::Payload force = can::decode_payload(answers.force[n].data);
    CHECK_TRUE(can::crc_ok(can::kSeatEstimate, answers.estimate[n].data));
    LONGS_EQUAL(n & 0xFFFFu, est.sample_counter);
    c.mismatches += est.words[0] != word(can::kSeatEstimate, double(e.x_r_m));
    c.mismatches += est.words[1] != word1(can::kSeatEstimate, double(e.v_r_m_per_s));
    c.mismatches += force.words[0] != word(can::kSeatEstimateForce, double(e.friction_n));
    c.mismatches += force.words[1] != word1(can::kSeatEstimateForce, double(e.bias_m_per_s2));
    c.mismatches += ((est.flags & can::kStuck) != 0) != e.stuck;
    c.mismatches += ((force.flags & can::kStuck) != 0) != e.stuck;
    if (n % 10 == 0) {
      const can::Payload friction = can::decode_payload(answers.friction[n / 10].data);
      const bool kinetic_ready = static_cast<double>(e.kinetic_samples) >= kinetic_needed;
      const bool static_ready = static_cast<double>(e.breakaways) >= static_needed;
      c.kinetic_published += kinetic_ready;
      c.static_published += static_ready;
      c.mismatches += friction.words[0] !=
                      (kinetic_ready ? word(can::kFrictionEstimate, double(e.kinetic_friction_n))
                                     : can::kUnsignedNotAvailable);
      c.mismatches += friction.words[1] !=
                      (static_ready ? word1(can::kFrictionEstimate, double(e.static_friction_n))
                                    : can::kUnsignedNotAvailable);
    }
  }
  c.final_kinetic_n = double(oracle.estimate().kinetic_friction_n);
  return c;
}

}  // namespace

TEST(EcuEstimator, PublishedEstimatesOfAReferenceRigRunEqualTheInProcessEstimatorBitForBit) {
  const std::vector<RigSample> measured = measured_rig(dir);
  host::EcuResult result;
  const Answers answers = run_node(measured, host::ScalarType::float64, result);
  const Comparison c = compare_with_oracle<double>(measured, answers);
  LONGS_EQUAL(0, c.mismatches);
  // Both paths of FrictionEstimate were exercised: not available at first, then published.
  const std::uint64_t cycles = measured.size() / 10 + 1;
  CHECK_TRUE(c.kinetic_published > 0 && c.kinetic_published < cycles);
  CHECK_TRUE(c.static_published > 0 && c.static_published < cycles);
  // The estimate learnt the rig's friction, not the node's start values (F_fk 45 N): within the
  // 5 % the estimator's validation holds it to (docs/IDENTIFICATION.md).
  DOUBLES_EQUAL(60.0, c.final_kinetic_n, 0.05 * 60.0);

  const auto json = nlohmann::json::parse(result.json);
  const auto& estimator = json["estimator"];
  LONGS_EQUAL(measured.size(), estimator["sensor_accepted"].get<long>());
  LONGS_EQUAL(measured.size(), estimator["samples_with_a_x"].get<long>());
  LONGS_EQUAL(measured.size(), estimator["samples_with_travel"].get<long>());
  LONGS_EQUAL(0, estimator["sensor_unused"].get<long>());
  STRCMP_EQUAL("", estimator["cannot_estimate"].get<std::string>().c_str());
  CHECK_TRUE(result.estimator_limits.empty());
}

TEST(EcuEstimator, FloatNodeEqualsTheInProcessFloatEstimatorBitForBit) {
  const std::vector<RigSample> measured = measured_rig(dir);
  host::EcuResult result;
  const Answers answers = run_node(measured, host::ScalarType::float32, result);
  LONGS_EQUAL(0, compare_with_oracle<float>(measured, answers).mismatches);
  // Float and double runs differ somewhere (the float oracle is not the double one).
  CHECK_TRUE(compare_with_oracle<double>(measured, answers).mismatches > 0);
}

TEST(EcuEstimator, WithoutSensorFramesTheNodeSaysWhatItCannotEstimate) {
  host::EcuRequest request = node_request();
  const std::uint64_t samples = 2000;
  request.max_frames = samples;
  auto tester = estimate_listener();
  host::EcuResult result;
  std::thread ecu([&] { result = host::run_ecu(request); });
  wait_for_node();
  Answers answers;
  for (std::uint64_t n = 0; n < samples; ++n)
    exchange(*tester, nullptr, can::make_input_frame(2.0 * std::sin(0.02 * double(n)), n), n,
             answers);
  ecu.join();
  for (const can::Frame& frame : answers.friction) {
    const can::Payload p = can::decode_payload(frame.data);
    LONGS_EQUAL(can::kUnsignedNotAvailable, p.words[0]);
    LONGS_EQUAL(can::kUnsignedNotAvailable, p.words[1]);
  }
  CHECK(result.estimator_limits.rfind("no SeatSensors samples (a_x, x_r)", 0) == 0);
  const auto json = nlohmann::json::parse(result.json);
  CHECK_TRUE(json["estimator"]["ffk"].is_null());
  CHECK_TRUE(json["estimator"]["ffs"].is_null());
  LONGS_EQUAL(0, json["estimator"]["sensor_frames"].get<long>());
}

TEST(EcuEstimator, FixedPointNodeRefusesTheEstimator) {
  host::EcuRequest request = node_request();
  request.scalar = host::ScalarType::fixed;
  try {
    host::run_ecu(request);
    FAIL("accepted");
  } catch (const std::exception& error) {
    CHECK(std::string(error.what()).rfind("--estimator: runs in double or float only", 0) == 0);
  }
}

// The estimator models no stops: on an end-stop scene it is refused, not run wrong in contact.
TEST(EcuEstimator, EndStopSceneRefusesTheEstimator) {
  host::EcuRequest request = node_request();
  request.setup.effects |= kEndStops;
  request.setup.stops.travel_m = 0.05;
  request.setup.stops.stiffness_n_per_m = 2.0e5;
  try {
    host::run_ecu(request);
    FAIL("accepted");
  } catch (const std::exception& error) {
    CHECK(std::string(error.what())
              .rfind("--estimator: the state estimator models the seat without end stops", 0) == 0);
  }
}

TEST_GROUP(SensorReceiver){};

TEST(SensorReceiver, KeepsTheGoodFrameForItsSampleAndRefusesBadOnes) {
  can::SensorReceiver receiver;
  double a_x = 0.0, x_r = 0.0;
  CHECK_FALSE(receiver.sample(0, a_x, x_r));  // nothing yet: not measured
  CHECK_TRUE(std::isnan(a_x) && std::isnan(x_r));
  CHECK(receiver.take(can::make_sensor_frame(0.5, 0.01, 7)) == can::SensorVerdict::accepted);
  CHECK_TRUE(receiver.sample(7, a_x, x_r));
  CHECK_EQUAL(0.5, a_x);
  CHECK_EQUAL(can::quantised_sensor(1, 0.01), x_r);
  // A travel sensor that is not fitted: a_x alone.
  CHECK(receiver.take(can::make_sensor_frame(0.25, std::nan(""), 8)) ==
        can::SensorVerdict::accepted);
  CHECK_TRUE(receiver.sample(8, a_x, x_r));
  CHECK_EQUAL(0.25, a_x);
  CHECK_TRUE(std::isnan(x_r));
  CHECK(receiver.take(can::make_sensor_frame(0.25, 0.0, 8)) == can::SensorVerdict::duplicate);
  can::Frame corrupt = can::make_sensor_frame(0.1, 0.0, 9);
  corrupt.data[5] ^= 0x10;
  CHECK(receiver.take(corrupt) == can::SensorVerdict::bad_crc);
  can::Frame short_frame = can::make_sensor_frame(0.1, 0.0, 9);
  short_frame.length = 6;
  CHECK(receiver.take(short_frame) == can::SensorVerdict::wrong_length);
  // The alive counter must advance with the sample counter (re-encoded, so the CRC is good).
  can::Payload payload = can::decode_payload(can::make_sensor_frame(0.1, 0.0, 9).data);
  payload.alive_counter = 3;
  CHECK(receiver.take(can::make_frame(can::kSeatSensors, payload)) ==
        can::SensorVerdict::alive_mismatch);
  // A frame whose sample has passed (or is overtaken) is not used for another sample.
  CHECK(receiver.take(can::make_sensor_frame(0.1, 0.0, 10)) == can::SensorVerdict::accepted);
  CHECK_FALSE(receiver.sample(11, a_x, x_r));
  CHECK_TRUE(std::isnan(a_x));
  CHECK(receiver.take(can::make_input_frame(0.1, 12)) == can::SensorVerdict::not_sensors);
  const can::SensorCounters& c = receiver.counters();
  LONGS_EQUAL(7, c.frames);
  LONGS_EQUAL(3, c.accepted);
  LONGS_EQUAL(4, c.refused);
  LONGS_EQUAL(2, c.used);
  LONGS_EQUAL(1, c.unused);
  LONGS_EQUAL(2, c.with_a_x);
  LONGS_EQUAL(1, c.with_travel);
}
