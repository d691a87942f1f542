// The SocketCAN endpoint's checks on every read and send (port/socketcan_frame.hpp), as pure
// functions: these hold on any Linux host, also one without AF_CAN, and cover what a vcan bus
// cannot produce (short, long and truncated reads, impossible lengths).
#include <cstring>

#include <linux/can/error.h>

#include "stickslip/port/socketcan_frame.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

namespace can = stickslip::can;
namespace port = stickslip::port;
using port::TransportStatus;

namespace {
canfd_frame raw_frame(canid_t id, std::uint8_t length) {
  canfd_frame raw{};
  raw.can_id = id;
  raw.len = length;
  for (int n = 0; n < CANFD_MAX_DLEN; ++n) raw.data[n] = static_cast<std::uint8_t>(0xA0 + n);
  return raw;
}
}  // namespace

TEST_GROUP(SocketCanFrame){};

TEST(SocketCanFrame, OnlyWholeClassicOrFdReadsAreFrames) {
  can::Frame frame;
  frame.id = 0x77;  // left alone by a malformed read
  const canfd_frame classic = raw_frame(0x123, 8);
  CHECK_FALSE(port::decode_socketcan_read(classic, CAN_MTU - 1, false, frame));
  CHECK_FALSE(port::decode_socketcan_read(classic, CAN_MTU + 1, false, frame));
  CHECK_FALSE(port::decode_socketcan_read(classic, 0, false, frame));
  CHECK_FALSE(port::decode_socketcan_read(classic, CAN_MTU, true, frame));
  CHECK_FALSE(port::decode_socketcan_read(raw_frame(0x123, 9), CAN_MTU, false, frame));
  CHECK_FALSE(port::decode_socketcan_read(raw_frame(0x123, 13), CANFD_MTU, false, frame));
  CHECK_FALSE(port::decode_socketcan_read(raw_frame(0x123, 65), CANFD_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(0x77, frame.id);

  CHECK_TRUE(port::decode_socketcan_read(classic, CAN_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(0x123, frame.id);
  UNSIGNED_LONGS_EQUAL(0, frame.flags);
  UNSIGNED_LONGS_EQUAL(8, frame.length);
  MEMCMP_EQUAL(classic.data, frame.data, 8);

  const canfd_frame fd = raw_frame(0x456, 64);
  CHECK_TRUE(port::decode_socketcan_read(fd, CANFD_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(can::kFd, frame.flags);
  UNSIGNED_LONGS_EQUAL(64, frame.length);  // never truncated to 8
  MEMCMP_EQUAL(fd.data, frame.data, 64);
}

TEST(SocketCanFrame, IdFlagsBecomeFrameKinds) {
  can::Frame frame;
  CHECK_TRUE(
      port::decode_socketcan_read(raw_frame(0x1ABCDEF0 | CAN_EFF_FLAG, 2), CAN_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(0x1ABCDEF0, frame.id);
  UNSIGNED_LONGS_EQUAL(can::kExtendedId, frame.flags);

  CHECK_TRUE(
      port::decode_socketcan_read(raw_frame(0x321 | CAN_RTR_FLAG, 4), CAN_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(can::kRemote, frame.flags);
  UNSIGNED_LONGS_EQUAL(4, frame.length);
  UNSIGNED_LONGS_EQUAL(0, frame.data[0]);  // a remote request carries no data

  CHECK_TRUE(port::decode_socketcan_read(raw_frame(CAN_ERR_FLAG | CAN_ERR_CRTL, CAN_ERR_DLC),
                                         CAN_MTU, false, frame));
  UNSIGNED_LONGS_EQUAL(CAN_ERR_CRTL, frame.id);
  UNSIGNED_LONGS_EQUAL(can::kErrorFrame, frame.flags);
  UNSIGNED_LONGS_EQUAL(CAN_ERR_DLC, frame.length);
}

TEST(SocketCanFrame, EncodeWritesTheRightSizeAndRefusesWhatNoBusCarries) {
  can::Frame frame;
  frame.id = 0x1ABCDEF0;
  frame.flags = can::kExtendedId;
  frame.length = 3;
  frame.data[0] = 1, frame.data[1] = 2, frame.data[2] = 3;
  canfd_frame raw{};
  std::size_t size = 0;
  STRCMP_EQUAL("ok", port::transport_status_name(port::encode_socketcan_write(frame, raw, size)));
  UNSIGNED_LONGS_EQUAL(CAN_MTU, size);
  UNSIGNED_LONGS_EQUAL(0x1ABCDEF0 | CAN_EFF_FLAG, raw.can_id);
  UNSIGNED_LONGS_EQUAL(3, raw.len);
  UNSIGNED_LONGS_EQUAL(3, raw.data[2]);

  frame.flags = can::kFd;
  frame.id = 0x100;
  frame.length = 48;
  STRCMP_EQUAL("ok", port::transport_status_name(port::encode_socketcan_write(frame, raw, size)));
  UNSIGNED_LONGS_EQUAL(CANFD_MTU, size);

  const auto refused = [&](std::uint32_t id, std::uint8_t flags, std::uint8_t length) {
    can::Frame bad;
    bad.id = id;
    bad.flags = flags;
    bad.length = length;
    return port::encode_socketcan_write(bad, raw, size) == TransportStatus::invalid_argument;
  };
  CHECK_TRUE(refused(0x800, 0, 1));                        // wider than 11 bits
  CHECK_TRUE(refused(0x20000000, can::kExtendedId, 1));    // wider than 29 bits
  CHECK_TRUE(refused(0x100, 0, 9));                        // classic > 8 bytes
  CHECK_TRUE(refused(0x100, can::kFd, 13));                // no DLC says 13
  CHECK_TRUE(refused(0x100, can::kFd | can::kRemote, 0));  // FD has no remote frames
  CHECK_TRUE(refused(0x004, can::kErrorFrame, 8));         // error frames come from drivers
  CHECK_FALSE(refused(0x100, can::kRemote, 8));            // a remote request for 8 bytes
}
