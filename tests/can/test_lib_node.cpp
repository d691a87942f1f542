// The lib/ ECU node (can/ecu_node.hpp) with the seats lib/ offers (can/node_seats.hpp), as the
// firmware runs it, against the host's `ecu` node: the same frames in give the same frames out,
// byte for byte, with faults on the bus too (lost frames held, duplicates, bad CRCs, foreign
// traffic); and the fixed-point seat's a_x words stay within one of the float seat's.
#include <cmath>
#include <cstdint>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/can/ecu_node.hpp"
#include "stickslip/can/node_seats.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/host/bus/ecu_node.hpp"

using namespace stickslip;

namespace {

// The firmware's seat (port/baremetal/src/node.cpp).
OscillatorParams firmware_seat() {
  OscillatorParams params;
  params.model = FrictionModel::stick_slip;
  params.kinetic_friction_n = params.static_friction_n = 45.0;
  params.dt_s = 1e-3;
  params.integrator = Integrator::exact;
  params.input_range_m_per_s2 = 32.768;
  params.displacement_range_m = 0.1;
  return params;
}

// A floor that makes the seat stick and slip: two tones, 4 s at 1 kHz.
double floor_acceleration(std::uint64_t n) {
  const double t = static_cast<double>(n) * 1e-3;
  return 1.1 * std::sin(2.0 * M_PI * 1.3 * t) + 0.6 * std::sin(2.0 * M_PI * 4.7 * t + 0.4);
}

// The SeatInput stream with faults: every 97th frame lost, every 211th sent twice, every 401st
// with a broken CRC (the good copy follows), a foreign frame every 50th.
std::vector<can::Frame> faulty_stream(std::uint64_t samples) {
  std::vector<can::Frame> frames;
  for (std::uint64_t n = 0; n < samples; ++n) {
    const can::Frame frame = can::make_input_frame(floor_acceleration(n), n);
    if (n % 50 == 0) {
      can::Frame foreign;
      foreign.id = 0x321;
      foreign.length = 8;
      frames.push_back(foreign);
    }
    if (n % 97 == 96) continue;
    if (n % 401 == 400) {
      can::Frame broken = frame;
      broken.data[0] ^= 0x5Au;
      frames.push_back(broken);
    }
    frames.push_back(frame);
    if (n % 211 == 210) frames.push_back(frame);
  }
  return frames;
}

struct Collect {
  std::vector<can::Frame> frames;
  std::uint64_t samples = 0;
  void send(const can::Frame& frame) { frames.push_back(frame); }
  void sampled(const can::NodeSample& /*sample*/) { ++samples; }
};

bool same_bytes(const can::Frame& a, const can::Frame& b) {
  if (a.id != b.id || a.length != b.length || a.flags != b.flags) return false;
  for (int i = 0; i < a.length; ++i)
    if (a.data[i] != b.data[i]) return false;
  return true;
}

template <typename Seat>
void configure_node(can::EcuNode<Seat>& node, can::OutputSet outputs) {
  CHECK(node.seat().configure(firmware_seat()).ok());
  can::EcuNodeParams params;
  params.outputs = outputs;
  params.checker.max_gap = 10;
  CHECK(node.configure(params) == Status::ok);
}

// The host `ecu` node in float with the firmware's outputs and gap policy, for the seat `params`.
host::EcuNodeConfig host_float_node(const OscillatorParams& params) {
  host::EcuNodeConfig config;
  config.setup.params = params;
  config.scalar = host::ScalarType::float32;
  config.outputs = can::OutputSet::motion;
  config.checker.max_gap = 10;
  return config;
}

// Frames of `a` whose bytes differ from the frame at the same place in `b` (same length).
std::size_t mismatched_frames(const std::vector<can::Frame>& a, const std::vector<can::Frame>& b) {
  std::size_t mismatched = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bytes(a[i], b[i])) ++mismatched;
  return mismatched;
}

}  // namespace

TEST_GROUP(LibEcuNode){};

TEST(LibEcuNode, FloatSeatSendsTheHostEcuNodesFramesByteForByteThroughFaults) {
  const std::vector<can::Frame> stream = faulty_stream(4000);
  host::EcuNode host_node(host_float_node(firmware_seat()));
  std::vector<can::Frame> host_frames;
  for (const can::Frame& frame : stream) host_node.on_frame(frame, 0, host_frames);

  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> node;
  configure_node(node, can::OutputSet::motion);
  Collect lib;
  for (const can::Frame& frame : stream) node.on_frame(frame, 0, lib);

  // 4000 samples (the lost ones held), two frames each.
  LONGS_EQUAL(4000, node.samples());
  LONGS_EQUAL(4000, lib.samples);
  LONGS_EQUAL(8000, lib.frames.size());
  LONGS_EQUAL(host_frames.size(), lib.frames.size());
  const std::size_t mismatched = mismatched_frames(lib.frames, host_frames);
  LONGS_EQUAL(0, mismatched);
  // The faults were seen, and counted alike.
  const can::FaultCounters& c = node.counters();
  CHECK(c.lost > 0 && c.duplicate > 0 && c.bad_crc > 0 && c.foreign_frames > 0);
  LONGS_EQUAL(host_node.counters().faults(), c.faults());
  LONGS_EQUAL(host_node.counters().held_samples, c.held_samples);
}

TEST(LibEcuNode, AChangedSeatIsCaughtByTheFrameComparison) {
  // The comparison above can fail: a seat with 1 N less friction sends other frames.
  const std::vector<can::Frame> stream = faulty_stream(4000);
  OscillatorParams changed = firmware_seat();
  changed.kinetic_friction_n = changed.static_friction_n = 44.0;
  host::EcuNode host_node(host_float_node(changed));
  std::vector<can::Frame> host_frames;
  for (const can::Frame& frame : stream) host_node.on_frame(frame, 0, host_frames);
  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> node;
  configure_node(node, can::OutputSet::motion);
  Collect lib;
  for (const can::Frame& frame : stream) node.on_frame(frame, 0, lib);
  LONGS_EQUAL(host_frames.size(), lib.frames.size());
  const std::size_t mismatched = mismatched_frames(lib.frames, host_frames);
  CHECK(mismatched > 1000);
}

TEST(LibEcuNode, FullSetSendsSeatStatsAndSceneWithNotAvailableStatisticsAndTheFaultCount) {
  // lib/'s seats keep no running statistics: SeatStats and SeatScene say not available; the
  // fault count in SeatScene is the checker's.
  can::EcuNode<can::OscillatorSeat<double, CoulombStickSlip>> node;
  configure_node(node, can::OutputSet::full);
  Collect lib;
  const std::vector<can::Frame> stream = faulty_stream(1000);
  for (const can::Frame& frame : stream) node.on_frame(frame, 0, lib);
  // Per sample SeatMotion and SeatForce, every 10th SeatStats and SeatScene.
  LONGS_EQUAL(2 * 1000 + 2 * 100, lib.frames.size());
  const can::Frame& scene = lib.frames[lib.frames.size() - 19];  // of sample 990
  LONGS_EQUAL(can::kSeatScene.id, scene.id);
  CHECK(can::crc_ok(can::kSeatScene, scene.data));
  const can::Payload p = can::decode_payload(scene.data);
  CHECK(can::not_available(can::kSeatScene.signals[0], p.words[0]));
  LONGS_EQUAL(node.counters().faults(), p.words[1]);
}

TEST(LibEcuNode, FixedPointSeatsAxWordsAreWithinOneOfTheFloatSeats) {
  // Q7.24 in scene units (the Cortex-M0+ build) against float on the same stream. One Q7.24
  // LSB of acceleration is (L/dt^2) 2^-24 = 1.8e-4 m/s^2 (L = 3.1 mm), and the step keeps a_x
  // within a few of them of float, below the word's 2^-10 m/s^2: two roundings of values that
  // close give words at most 1 apart.
  const std::vector<can::Frame> stream = faulty_stream(4000);
  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> reference;
  configure_node(reference, can::OutputSet::motion);
  can::EcuNode<can::ScaledSeat<Fixed32, CoulombStickSlip>> fixed;
  configure_node(fixed, can::OutputSet::motion);
  Collect a, b;
  for (const can::Frame& frame : stream) {
    reference.on_frame(frame, 0, a);
    fixed.on_frame(frame, 0, b);
  }
  LONGS_EQUAL(a.frames.size(), b.frames.size());
  int worst = 0;
  for (std::size_t i = 0; i < a.frames.size(); i += 2) {  // SeatMotion frames
    const can::Payload pa = can::decode_payload(a.frames[i].data);
    const can::Payload pb = can::decode_payload(b.frames[i].data);
    CHECK(can::crc_ok(can::kSeatMotion, b.frames[i].data));
    LONGS_EQUAL(pa.sample_counter, pb.sample_counter);
    const int diff = std::abs(can::word_as_signed(pa.words[0]) - can::word_as_signed(pb.words[0]));
    if (diff > worst) worst = diff;
  }
  CHECK_TEXT(worst <= 1, "a_x words differ by more than 1 between the Q7.24 and the float seat");
}
