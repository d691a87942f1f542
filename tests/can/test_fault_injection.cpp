// Fault injection: every fault kind is sent over the loopback bus to the ECU node; the right
// counter moves by exactly the injected amount and the faulty frame's sample is never used (it
// carries a_u = 7 m/s^2, a value no good frame has; held samples are flagged).
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/bus/ecu_node.hpp"
#include "stickslip/port/loopback_transport.hpp"

using namespace stickslip;

namespace {

constexpr double kFaultyValue = 7.0;  // m/s^2: only faulty frames carry it

double good_value(std::uint64_t n) {
  return 0.125 * static_cast<double>(n % 16) - 0.9375;
}

std::uint64_t clock_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

can::Frame input_frame(std::uint16_t counter, std::uint8_t alive, double a_u) {
  can::Payload payload;
  payload.sample_counter = counter;
  payload.alive_counter = alive;
  payload.words[0] = can::quantise(can::kSeatInput.signals[0], a_u).word;
  payload.words[1] = static_cast<std::uint16_t>(can::kSignedNotAvailable);
  return can::make_frame(can::kSeatInput, payload);
}

can::Frame faulty_frame(std::uint64_t n) {
  return can::make_input_frame(kFaultyValue, n);
}

}  // namespace

TEST_GROUP(FaultInjection) {
  std::unique_ptr<port::Transport> sender, node_port;
  std::unique_ptr<host::EcuNode> node;
  std::vector<can::Frame> outputs;

  void setup() override {
    sender = port::make_loopback_transport();
    node_port = port::make_loopback_transport();
    CHECK(sender->open("loopback") == port::TransportStatus::ok);
    CHECK(node_port->open("loopback") == port::TransportStatus::ok);
    host::EcuNodeConfig config;
    config.setup.params.model = FrictionModel::stick_slip;
    config.setup.params.integrator = Integrator::exact;
    config.setup.params.kinetic_friction_n = config.setup.params.static_friction_n = 45.0;
    config.checker.max_gap = 10;
    config.checker.silence_timeout_ns = 20000000;  // 20 ms
    node = std::make_unique<host::EcuNode>(config);
    node->start(clock_ns());
  }
  void teardown() override {
    node.reset();
    sender.reset();
    node_port.reset();
  }

  can::FrameVerdict deliver(const can::Frame& frame) {
    CHECK(sender->send(frame) == port::TransportStatus::ok);
    can::Frame received;
    CHECK(node_port->receive(received, 1000) == port::TransportStatus::ok);
    outputs.clear();
    return node->on_frame(received, clock_ns(), outputs);
  }
  void good(std::uint64_t n) {
    CHECK(deliver(can::make_input_frame(good_value(n), n)) == can::FrameVerdict::accepted);
  }
  void good_range(std::uint64_t first, std::uint64_t last) {
    for (std::uint64_t n = first; n <= last; ++n) good(n);
  }
  // No row carries the faulty value, and every row that is not flagged held has the good value
  // of its sample index.
  void check_no_faulty_sample_used() {
    const host::NodeTrace& trace = node->trace();
    for (std::size_t row = 0; row < trace.a_u.size(); ++row) {
      CHECK(trace.a_u[row] != kFaultyValue);
      if (!trace.held[row]) CHECK_EQUAL(good_value(trace.index[row]), trace.a_u[row]);
    }
  }
  std::uint64_t held_rows() const {
    std::uint64_t held = 0;
    for (std::uint8_t h : node->trace().held) held += h;
    return held;
  }
  void check_only(std::uint64_t can::FaultCounters::*counter, std::uint64_t expected) {
    can::FaultCounters c = node->counters();
    LONGS_EQUAL(expected, c.*counter);
    c.*counter = 0;
    // Every other fault counter stayed at zero.
    LONGS_EQUAL(0, c.duplicate + c.out_of_order + c.bad_crc + c.wrong_length + c.foreign_frames +
                       c.can_fd + c.error_frame + c.remote_frame + c.alive_mismatch +
                       c.invalid_signal + c.resync + c.silence);
  }
};

TEST(FaultInjection, LostFramesAreCountedAndTheirSamplesHeldAndFlagged) {
  good_range(0, 2);
  good_range(5, 6);  // 3 and 4 lost
  const can::FaultCounters& c = node->counters();
  LONGS_EQUAL(2, c.lost);
  LONGS_EQUAL(2, c.held_samples);
  check_only(&can::FaultCounters::lost, 2);
  LONGS_EQUAL(7, node->samples());  // time never slips: one row per sample index
  const host::NodeTrace& trace = node->trace();
  LONGS_EQUAL(1, trace.held[3]);
  LONGS_EQUAL(1, trace.held[4]);
  CHECK_EQUAL(good_value(2), trace.a_u[3]);  // the last good sample, held
  CHECK_EQUAL(good_value(2), trace.a_u[4]);
  LONGS_EQUAL(2, held_rows());
  check_no_faulty_sample_used();
  // The held rows are announced on the bus too (SeatMotion flag "held").
  bool held_flag_sent = false;
  good(7);
  good_range(9, 9);  // 8 lost: this frame's outputs start with the held sample
  for (const can::Frame& f : outputs)
    if (f.id == can::kSeatMotion.id && (can::decode_payload(f.data).flags & can::kHeld))
      held_flag_sent = true;
  CHECK_TRUE(held_flag_sent);
}

TEST(FaultInjection, DuplicateIsRefusedAndCounted) {
  good_range(0, 2);
  can::Frame duplicate = can::make_input_frame(kFaultyValue, 2);
  CHECK(deliver(duplicate) == can::FrameVerdict::duplicate);
  good_range(3, 4);
  check_only(&can::FaultCounters::duplicate, 1);
  LONGS_EQUAL(5, node->samples());
  LONGS_EQUAL(0, held_rows());
  check_no_faulty_sample_used();
}

TEST(FaultInjection, OutOfOrderFrameIsRefusedAndItsSlotHeld) {
  good_range(0, 2);
  good(4);  // 3 is late: counted lost and held
  CHECK(deliver(faulty_frame(3)) == can::FrameVerdict::out_of_order);
  good_range(5, 6);
  const can::FaultCounters& c = node->counters();
  LONGS_EQUAL(1, c.out_of_order);
  LONGS_EQUAL(1, c.lost);
  LONGS_EQUAL(0, c.duplicate + c.bad_crc + c.resync + c.alive_mismatch);
  LONGS_EQUAL(7, node->samples());
  check_no_faulty_sample_used();
}

TEST(FaultInjection, BadCrcIsRefusedAndCounted) {
  good_range(0, 2);
  can::Frame corrupted = faulty_frame(3);
  corrupted.data[5] ^= 0x10;  // one bit flipped on the way
  CHECK(deliver(corrupted) == can::FrameVerdict::bad_crc);
  good_range(4, 5);
  const can::FaultCounters& c = node->counters();
  LONGS_EQUAL(1, c.bad_crc);
  LONGS_EQUAL(1, c.lost);  // its sample is missing from the sequence: held
  LONGS_EQUAL(1, held_rows());
  check_no_faulty_sample_used();
}

TEST(FaultInjection, WrongLengthIsRefusedAndCounted) {
  good_range(0, 1);
  for (std::uint8_t length : {0, 5, 7}) {
    can::Frame shortened = faulty_frame(2);
    shortened.length = length;
    CHECK(deliver(shortened) == can::FrameVerdict::wrong_length);
  }
  good(2);
  check_only(&can::FaultCounters::wrong_length, 3);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, ForeignAndExtendedIdsAreCountedApartFromFaults) {
  good(0);
  can::Frame foreign = faulty_frame(1);
  foreign.id = 0x123;
  CHECK(deliver(foreign) == can::FrameVerdict::foreign_frame);
  can::Frame extended = faulty_frame(1);
  extended.flags = can::kExtendedId;  // 0x100 as a 29-bit id is another message
  CHECK(deliver(extended) == can::FrameVerdict::foreign_frame);
  good(1);
  LONGS_EQUAL(0, node->counters().faults());  // other traffic on the bus is no fault
  check_only(&can::FaultCounters::foreign_frames, 2);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, CanFdFrameIsRefusedAndCountedNeverTruncated) {
  good(0);
  can::Frame fd = faulty_frame(1);
  fd.flags = can::kFd;
  CHECK(deliver(fd) == can::FrameVerdict::can_fd);  // even with 8 bytes and a good CRC
  fd.length = 64;
  CHECK(deliver(fd) == can::FrameVerdict::can_fd);
  good(1);
  check_only(&can::FaultCounters::can_fd, 2);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, ErrorFrameIsRefusedAndCounted) {
  good(0);
  can::Frame error = faulty_frame(1);
  error.flags = can::kErrorFrame;
  CHECK(deliver(error) == can::FrameVerdict::error_frame);
  good(1);
  check_only(&can::FaultCounters::error_frame, 1);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, RemoteFrameIsRefusedAndCounted) {
  good(0);
  can::Frame remote = faulty_frame(1);
  remote.flags = can::kRemote;
  CHECK(deliver(remote) == can::FrameVerdict::remote_frame);
  good(1);
  check_only(&can::FaultCounters::remote_frame, 1);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, AliveCounterMismatchIsRefusedAndCounted) {
  good_range(0, 2);
  // Right sample counter and CRC, but the alive counter did not advance (a stuck sender).
  CHECK(deliver(input_frame(3, 2, kFaultyValue)) == can::FrameVerdict::alive_mismatch);
  good_range(3, 4);
  check_only(&can::FaultCounters::alive_mismatch, 1);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, NotAvailableSignalIsCountedAndHeld) {
  good_range(0, 2);
  can::Payload payload = can::decode_payload(can::make_input_frame(0.0, 3).data);
  payload.words[0] = static_cast<std::uint16_t>(can::kSignedNotAvailable);
  CHECK(deliver(can::make_frame(can::kSeatInput, payload)) == can::FrameVerdict::invalid_signal);
  good_range(4, 5);
  check_only(&can::FaultCounters::invalid_signal, 1);
  LONGS_EQUAL(6, node->samples());
  LONGS_EQUAL(1, node->trace().held[3]);
  CHECK_EQUAL(good_value(2), node->trace().a_u[3]);
  check_no_faulty_sample_used();
}

TEST(FaultInjection, GapBeyondTheBoundIsACountedResyncWithoutHolding) {
  good_range(0, 2);
  good_range(20, 21);  // 17 lost > max_gap 10
  check_only(&can::FaultCounters::resync, 1);
  LONGS_EQUAL(0, node->counters().lost);
  LONGS_EQUAL(17, node->counters().skipped);  // counted, not filled in
  LONGS_EQUAL(5, node->samples());
  LONGS_EQUAL(0, held_rows());
  // Every counter from the first to the last is accounted for.
  const can::FaultCounters& c = node->counters();
  LONGS_EQUAL(21 - 0 + 1, c.accepted + c.invalid_signal + c.lost + c.skipped);
  // The rows carry the sender's sample numbers, across the gap.
  LONGS_EQUAL(0, node->first_sample());
  LONGS_EQUAL(21, node->last_sample());
  LONGS_EQUAL(2, node->trace().sample[2]);
  LONGS_EQUAL(20, node->trace().sample[3]);
}

TEST(FaultInjection, HeldRowsCarryTheSampleNumbersTheyStandInFor) {
  good_range(65533, 65535);
  good_range(2, 3);  // the counter wraps; 0 and 1 lost and held
  LONGS_EQUAL(2, node->counters().lost);
  const host::NodeTrace& trace = node->trace();
  LONGS_EQUAL(7, trace.sample.size());
  for (std::size_t row = 0; row < trace.sample.size(); ++row)
    LONGS_EQUAL(65533 + static_cast<long>(row), trace.sample[row]);  // counts on past 2^16
  LONGS_EQUAL(1, trace.held[3]);
  LONGS_EQUAL(1, trace.held[4]);
  LONGS_EQUAL(0, trace.held[5]);
}

TEST(FaultInjection, RestartedSenderIsFollowedAfterAShortRun) {
  good_range(1000, 1005);
  // The sender restarts from 0: a few frames are refused as out of order, then a resync.
  CHECK(deliver(can::make_input_frame(good_value(0), 0)) == can::FrameVerdict::out_of_order);
  CHECK(deliver(can::make_input_frame(good_value(1), 1)) == can::FrameVerdict::out_of_order);
  CHECK(deliver(can::make_input_frame(good_value(2), 2)) == can::FrameVerdict::out_of_order);
  CHECK(deliver(can::make_input_frame(good_value(3), 3)) == can::FrameVerdict::accepted);
  good_range(4, 6);
  LONGS_EQUAL(3, node->counters().out_of_order);
  LONGS_EQUAL(1, node->counters().resync);
}

TEST(FaultInjection, OwnOutputIdsOnTheBusAreIgnoredNotFaults) {
  good(0);
  can::Frame other_node = faulty_frame(1);
  other_node.id = can::kSeatMotion.id;
  CHECK(deliver(other_node) == can::FrameVerdict::ignored_output);
  good(1);
  LONGS_EQUAL(1, node->counters().ignored_output);
  LONGS_EQUAL(0, node->counters().faults());
  check_no_faulty_sample_used();
}

TEST(FaultInjection, BusSilenceBeyondTheTimeoutIsCountedOncePerSilence) {
  can::Frame received;
  // Waiting for the first frame is not a silence.
  CHECK(node_port->receive(received, 30) == port::TransportStatus::timeout);
  node->on_idle(clock_ns());
  LONGS_EQUAL(0, node->counters().silence);
  good_range(0, 1);
  // Nothing on the bus for 30 ms (> 20 ms): one silence, however often the node looks.
  for (int i = 0; i < 3; ++i) {
    CHECK(node_port->receive(received, 15) == port::TransportStatus::timeout);
    node->on_idle(clock_ns());
  }
  LONGS_EQUAL(1, node->counters().silence);
  good(2);  // the stream is back
  CHECK(node_port->receive(received, 30) == port::TransportStatus::timeout);
  node->on_idle(clock_ns());
  check_only(&can::FaultCounters::silence, 2);
  LONGS_EQUAL(3, node->samples());
}

TEST(FaultInjection, TenSecondsOfRandomFramesLeaveTheNodeRunning) {
  // The in-process analogue of `cangen -g 0 -I r -L r -D r` mixed with FD, remote and error
  // frames: 10 s of a 1 kHz bus, every frame random.
  good_range(0, 9);
  std::mt19937 random(12345);
  const int frames = 10000;
  std::uint64_t sent = 0;
  for (int i = 0; i < frames; ++i) {
    can::Frame frame;
    const std::uint32_t r = random();
    frame.id = (r & 3u) == 0 ? can::kSeatInput.id : ((r >> 2) & can::kStandardIdMask);
    const std::uint32_t kind = (r >> 13) & 15u;
    frame.flags = kind == 0   ? can::kFd
                  : kind == 1 ? can::kRemote
                  : kind == 2 ? can::kErrorFrame
                  : kind == 3 ? can::kExtendedId
                              : 0;
    if (frame.flags == can::kExtendedId) frame.id = random() & can::kExtendedIdMask;
    frame.length =
        static_cast<std::uint8_t>(frame.flags == can::kFd ? random() % 65u : random() % 9u);
    for (std::uint8_t b = 0; b < frame.length; ++b)
      frame.data[b] = static_cast<std::uint8_t>(random());
    CHECK(sender->send(frame) == port::TransportStatus::ok);
    can::Frame received;
    CHECK(node_port->receive(received, 1000) == port::TransportStatus::ok);
    node->on_frame(received, clock_ns(), outputs);
    outputs.clear();
    ++sent;
  }
  const can::FaultCounters c = node->counters();
  LONGS_EQUAL(10 + sent, c.frames);
  // Every frame got exactly one verdict.
  LONGS_EQUAL(c.frames, c.accepted + c.ignored_output + c.duplicate + c.out_of_order + c.bad_crc +
                            c.wrong_length + c.foreign_frames + c.can_fd + c.error_frame +
                            c.remote_frame + c.alive_mismatch + c.invalid_signal);
  CHECK(c.bad_crc > 0 && c.wrong_length > 0 && c.foreign_frames > 0 && c.can_fd > 0 &&
        c.error_frame > 0 && c.remote_frame > 0);
  // Still running: a clean stream is followed again within a few frames, and the model's
  // output stays finite.
  const std::uint64_t before = node->samples();
  std::uint64_t accepted = 0;
  for (std::uint64_t n = 20000; n < 20100; ++n)
    accepted += deliver(can::make_input_frame(good_value(n), n)) == can::FrameVerdict::accepted;
  CHECK(accepted >= 100 - can::ReceiveChecker::kRestartRun);
  CHECK(node->samples() >= before + accepted);
  for (double x : node->trace().x_r) CHECK(std::isfinite(x));
}
