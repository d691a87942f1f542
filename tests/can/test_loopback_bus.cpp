// The in-process loopback bus (port/): delivery to every other endpoint, filters, bounded queue
// with drop counting, timeouts, timestamps, frame validation.
#include <cstring>
#include <memory>

#include "CppUTest/TestHarness.h"
#include "stickslip/port/loopback_transport.hpp"
#include "stickslip/port/socketcan_transport.hpp"
#include "stickslip/port/transport.hpp"

using namespace stickslip;
using port::TransportStatus;

namespace {

can::Frame frame_with_id(std::uint32_t id, std::uint8_t first_byte = 0) {
  can::Frame frame;
  frame.id = id;
  frame.length = 8;
  frame.data[0] = first_byte;
  return frame;
}

std::unique_ptr<port::Transport> open_loopback(
    std::size_t queue = port::kLoopbackDefaultQueueFrames) {
  auto transport = port::make_loopback_transport(queue);
  if (transport->open("loopback") != TransportStatus::ok) return nullptr;
  return transport;
}

}  // namespace

TEST_GROUP(LoopbackBus){};

TEST(LoopbackBus, EveryOtherEndpointReceivesInOrderButNeverItsOwnFrames) {
  auto a = open_loopback(), b = open_loopback(), c = open_loopback();
  CHECK(a && b && c);
  for (std::uint8_t i = 0; i < 5; ++i)
    LONGS_EQUAL(static_cast<int>(TransportStatus::ok),
                static_cast<int>(a->send(frame_with_id(0x100, i))));
  can::Frame got;
  for (port::Transport* receiver : {b.get(), c.get()}) {
    for (std::uint8_t i = 0; i < 5; ++i) {
      LONGS_EQUAL(static_cast<int>(TransportStatus::ok),
                  static_cast<int>(receiver->receive(got, 0)));
      LONGS_EQUAL(i, got.data[0]);
      CHECK(got.timestamp_ns > 0);
    }
    LONGS_EQUAL(static_cast<int>(TransportStatus::timeout),
                static_cast<int>(receiver->receive(got, 0)));
  }
  LONGS_EQUAL(static_cast<int>(TransportStatus::timeout), static_cast<int>(a->receive(got, 0)));
  LONGS_EQUAL(5, a->counters().frames_sent);
  LONGS_EQUAL(5, b->counters().frames_received);
}

TEST(LoopbackBus, TimestampsDoNotGoBackwards) {
  auto a = open_loopback(), b = open_loopback();
  std::uint64_t previous = 0;
  for (int i = 0; i < 100; ++i) {
    a->send(frame_with_id(0x100));
    can::Frame got;
    LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
    CHECK(got.timestamp_ns >= previous);
    previous = got.timestamp_ns;
  }
}

TEST(LoopbackBus, FiltersPassOnlyMatchingIds) {
  auto a = open_loopback(), b = open_loopback();
  const port::ReceiveFilter outputs{0x180, 0x7FC};  // 0x180..0x183
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->set_filters(&outputs, 1)));
  for (std::uint32_t id : {0x100u, 0x180u, 0x183u, 0x184u, 0x17Fu}) a->send(frame_with_id(id));
  can::Frame got;
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
  LONGS_EQUAL(0x180, got.id);
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
  LONGS_EQUAL(0x183, got.id);
  LONGS_EQUAL(static_cast<int>(TransportStatus::timeout), static_cast<int>(b->receive(got, 0)));
  // No filters: everything again.
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->set_filters(nullptr, 0)));
  a->send(frame_with_id(0x100));
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
}

TEST(LoopbackBus, FullReceiveQueueDropsAndCountsTheOverflow) {
  auto a = open_loopback(), b = open_loopback(4);
  for (std::uint8_t i = 0; i < 10; ++i) a->send(frame_with_id(0x100, i));
  LONGS_EQUAL(6, b->counters().receive_drops);
  can::Frame got;
  for (std::uint8_t i = 0; i < 4; ++i) {
    LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
    LONGS_EQUAL(i, got.data[0]);  // the oldest are kept, the newest dropped
  }
  LONGS_EQUAL(static_cast<int>(TransportStatus::timeout), static_cast<int>(b->receive(got, 0)));
}

TEST(LoopbackBus, ReceiveWaitsForTheTimeoutWhenNothingArrives) {
  auto a = open_loopback();
  can::Frame got;
  LONGS_EQUAL(static_cast<int>(TransportStatus::timeout), static_cast<int>(a->receive(got, 20)));
}

TEST(LoopbackBus, FramesTheBusCannotCarryAreRefused) {
  auto a = open_loopback(), b = open_loopback();
  can::Frame too_long = frame_with_id(0x100);
  too_long.length = 9;
  LONGS_EQUAL(static_cast<int>(TransportStatus::invalid_argument),
              static_cast<int>(a->send(too_long)));
  can::Frame bad_id = frame_with_id(0x800);
  LONGS_EQUAL(static_cast<int>(TransportStatus::invalid_argument),
              static_cast<int>(a->send(bad_id)));
  LONGS_EQUAL(2, a->counters().send_failures);
  // CAN FD and extended frames are carried (so that faults can be injected).
  can::Frame fd = frame_with_id(0x100);
  fd.flags = can::kFd;
  fd.length = 64;
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(a->send(fd)));
  can::Frame extended = frame_with_id(0x1ABCDEF);
  extended.flags = can::kExtendedId;
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(a->send(extended)));
  can::Frame got;
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(b->receive(got, 0)));
  LONGS_EQUAL(64, got.length);
}

TEST(LoopbackBus, ClosedEndpointsNeitherSendNorReceive) {
  auto a = open_loopback(), b = open_loopback();
  b->close();
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok),
              static_cast<int>(a->send(frame_with_id(0x100))));
  can::Frame got;
  LONGS_EQUAL(static_cast<int>(TransportStatus::closed), static_cast<int>(b->receive(got, 0)));
  LONGS_EQUAL(static_cast<int>(TransportStatus::closed),
              static_cast<int>(b->send(frame_with_id(0x100))));
  auto unopened = port::make_loopback_transport();
  LONGS_EQUAL(static_cast<int>(TransportStatus::no_such_interface),
              static_cast<int>(unopened->open("can7")));
}

TEST(LoopbackBus, MakeTransportAndDefaultBusName) {
  auto transport = port::make_transport("loopback");
  LONGS_EQUAL(static_cast<int>(TransportStatus::ok), static_cast<int>(transport->open("loopback")));
  const std::string name = port::default_bus_name();
  if (!port::kernel_has_can()) STRCMP_EQUAL("loopback", name.c_str());
  CHECK(name == "loopback" || name == "vcan0");
  STRCMP_EQUAL("buffer full", port::transport_status_name(TransportStatus::buffer_full));
  STRCMP_EQUAL("timeout", port::transport_status_name(TransportStatus::timeout));
}
