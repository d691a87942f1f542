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

// The firmware's seat, as each lib seat takes it.
template <typename Seat>
ConfigResult configure_seat(Seat& seat) {
  return seat.configure(firmware_seat());
}
template <typename T, typename Law>
ConfigResult configure_seat(can::ObserverSeat<T, Law>& seat) {
  return seat.configure(can::seat_observer_params(firmware_seat()));
}

template <typename Seat>
void configure_node(can::EcuNode<Seat>& node, can::OutputSet outputs) {
  CHECK(configure_seat(node.seat()).ok());
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

// What the host `ecu` node sends for `stream`, and the faults it counted.
struct HostRun {
  std::vector<can::Frame> frames;
  std::uint64_t faults = 0, held_samples = 0;
};
HostRun run_host_node(const host::EcuNodeConfig& config, const std::vector<can::Frame>& stream) {
  host::EcuNode node(config);
  HostRun run;
  for (const can::Frame& frame : stream) node.on_frame(frame, 0, run.frames);
  run.faults = node.counters().faults();
  run.held_samples = node.counters().held_samples;
  return run;
}

// What the lib node with the firmware's seat configuration sends for `stream`.
template <typename Seat>
Collect run_lib_node(can::EcuNode<Seat>& node, can::OutputSet outputs,
                     const std::vector<can::Frame>& stream) {
  configure_node(node, outputs);
  Collect collected;
  for (const can::Frame& frame : stream) node.on_frame(frame, 0, collected);
  return collected;
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
  const HostRun host = run_host_node(host_float_node(firmware_seat()), stream);
  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> node;
  const Collect lib = run_lib_node(node, can::OutputSet::motion, stream);

  // 4000 samples (the lost ones held), two frames each.
  LONGS_EQUAL(4000, node.samples());
  LONGS_EQUAL(4000, lib.samples);
  LONGS_EQUAL(8000, lib.frames.size());
  LONGS_EQUAL(host.frames.size(), lib.frames.size());
  LONGS_EQUAL(0, mismatched_frames(lib.frames, host.frames));
  // The faults were seen, and counted alike.
  const can::FaultCounters& c = node.counters();
  CHECK(c.lost > 0 && c.duplicate > 0 && c.bad_crc > 0 && c.foreign_frames > 0);
  LONGS_EQUAL(host.faults, c.faults());
  LONGS_EQUAL(host.held_samples, c.held_samples);
}

TEST(LibEcuNode, AChangedSeatIsCaughtByTheFrameComparison) {
  // The comparison above can fail: a seat with 1 N less friction sends other frames.
  const std::vector<can::Frame> stream = faulty_stream(4000);
  OscillatorParams changed = firmware_seat();
  changed.kinetic_friction_n = changed.static_friction_n = 44.0;
  const HostRun host = run_host_node(host_float_node(changed), stream);
  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> node;
  const Collect lib = run_lib_node(node, can::OutputSet::motion, stream);
  LONGS_EQUAL(host.frames.size(), lib.frames.size());
  CHECK(mismatched_frames(lib.frames, host.frames) > 1000);
}

TEST(LibEcuNode, FullSetSendsSeatStatsAndSceneWithNotAvailableStatisticsAndTheFaultCount) {
  // OscillatorSeat keeps no running statistics: SeatStats and SeatScene say not available; the
  // fault count in SeatScene is the checker's.
  can::EcuNode<can::OscillatorSeat<double, CoulombStickSlip>> node;
  const Collect lib = run_lib_node(node, can::OutputSet::full, faulty_stream(1000));
  // Per sample SeatMotion and SeatForce, every 10th SeatStats and SeatScene.
  LONGS_EQUAL(2 * 1000 + 2 * 100, lib.frames.size());
  const can::Frame& scene = lib.frames[lib.frames.size() - 19];  // of sample 990
  LONGS_EQUAL(can::kSeatScene.id, scene.id);
  CHECK(can::crc_ok(can::kSeatScene, scene.data));
  const can::Payload p = can::decode_payload(scene.data);
  CHECK(can::not_available(can::kSeatScene.signals[0], p.words[0]));
  LONGS_EQUAL(node.counters().faults(), p.words[1]);
}

namespace {

// A seat with a statistics window (the Cortex-M4F firmware's observer, the Cortex-M0+'s window
// over its words) against the host `ecu` node with the full output set, over 12 s: window blocks
// complete every second and the window fills at 10 s. SeatStats says not available for the first
// `not_available_frames` of its frames.
template <typename Seat>
void seat_sends_the_host_nodes_full_set(can::EcuNode<Seat>& node, host::ScalarType scalar,
                                        int not_available_frames) {
  const std::uint64_t samples = 12000;
  const std::vector<can::Frame> stream = faulty_stream(samples);
  host::EcuNodeConfig config = host_float_node(firmware_seat());
  config.scalar = scalar;
  config.outputs = can::OutputSet::full;
  const HostRun host = run_host_node(config, stream);
  const Collect lib = run_lib_node(node, can::OutputSet::full, stream);

  // Per sample SeatMotion and SeatForce, every 10th SeatStats and SeatScene.
  LONGS_EQUAL(2 * samples + 2 * (samples / 10), lib.frames.size());
  LONGS_EQUAL(host.frames.size(), lib.frames.size());
  LONGS_EQUAL(0, mismatched_frames(lib.frames, host.frames));
  // The statistics compared are figures: not available until the first block (1 s) completes,
  // then T_ax and p that move with every block, and K.
  int not_available = 0;
  std::vector<std::uint16_t> t_ax_words;
  for (const can::Frame& frame : lib.frames) {
    if (frame.id != can::kSeatStats.id) continue;
    const can::Payload p = can::decode_payload(frame.data);
    if (can::not_available(can::kSeatStats.signals[0], p.words[0])) {
      ++not_available;
    } else if (t_ax_words.empty() || t_ax_words.back() != p.words[0]) {
      t_ax_words.push_back(p.words[0]);
    }
  }
  LONGS_EQUAL(not_available_frames, not_available);
  CHECK(t_ax_words.size() >= 10);
  const can::Frame& last_scene = lib.frames[lib.frames.size() - 19];  // of sample 11990
  LONGS_EQUAL(can::kSeatScene.id, last_scene.id);
  const can::Payload scene = can::decode_payload(last_scene.data);
  CHECK_FALSE(can::not_available(can::kSeatScene.signals[0], scene.words[0]));
}

template <typename T>
void observer_seat_sends_the_host_nodes_full_set(host::ScalarType scalar) {
  can::EcuNode<can::ObserverSeat<T, CoulombStickSlip>> node;
  // Samples 0, 10, ..., 990: the first block completes with sample 1000, and its SeatStats has it.
  seat_sends_the_host_nodes_full_set(node, scalar, 100);
  CHECK(node.seat().observer().window().samples == 10000);
}

}  // namespace

TEST(LibEcuNode, FloatObserverSeatSendsTheHostEcuNodesFullSetByteForByteThroughFaults) {
  observer_seat_sends_the_host_nodes_full_set<float>(host::ScalarType::float32);
}

TEST(LibEcuNode, DoubleObserverSeatSendsTheHostEcuNodesFullSetByteForByteThroughFaults) {
  observer_seat_sends_the_host_nodes_full_set<double>(host::ScalarType::float64);
}

TEST(LibEcuNode, Fixed32HostNodeSendsTheCortexM0plusSeatsFramesByteForByteThroughFaults) {
  // `ecu --scalar fixed32`: the host node runs the firmware's Q7.24 seat with its integer word
  // scales, so its frames are the Cortex-M0+ firmware's.
  const std::vector<can::Frame> stream = faulty_stream(4000);
  host::EcuNodeConfig config = host_float_node(firmware_seat());
  config.scalar = host::ScalarType::fixed32;
  const HostRun host = run_host_node(config, stream);
  can::EcuNode<can::ScaledSeat<Fixed32, CoulombStickSlip>> node;
  const Collect lib = run_lib_node(node, can::OutputSet::motion, stream);
  LONGS_EQUAL(8000, lib.frames.size());
  LONGS_EQUAL(host.frames.size(), lib.frames.size());
  LONGS_EQUAL(0, mismatched_frames(lib.frames, host.frames));
  LONGS_EQUAL(host.faults, node.counters().faults());
  // And they are not the float seat's frames: the comparison sees the scalar.
  can::EcuNode<can::OscillatorSeat<float, CoulombStickSlip>> float_node;
  const Collect floats = run_lib_node(float_node, can::OutputSet::motion, stream);
  CHECK(mismatched_frames(floats.frames, host.frames) > 100);
}

TEST(LibEcuNode, Fixed32HostNodeSendsTheCortexM0plusSeatsFullSetWithItsWordWindowByteForByte) {
  can::EcuNode<can::ScaledSeat<Fixed32, CoulombStickSlip>> node;
  // Samples 0, 10, ..., 1000: the first block completes with sample 1000 and its figures are
  // published kStages samples later.
  static_assert(can::WordWindow<can::kSeatWindowBlocks>::kStages == 5, "published at 1005");
  seat_sends_the_host_nodes_full_set(node, host::ScalarType::fixed32, 101);
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
