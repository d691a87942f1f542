// The CAN codec and receive checker as an MCU uses them (this binary links the core alone):
// encoding, CRC, decoding and checking a stream with faults make zero heap allocations.
#include <cstdint>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/can/receive_checker.hpp"
#include "support/allocation_counter.hpp"

using namespace stickslip::can;

TEST_GROUP(CanCodecNoAllocation){};

TEST(CanCodecNoAllocation, EncodeDecodeAndCheckNeverTouchTheHeap) {
  ReceiveChecker checker;
  std::uint64_t accepted = 0, refused = 0;
  double sum = 0.0;
  stickslip::test::start_counting_allocations();
  for (std::uint64_t n = 0; n < 10000; ++n) {
    const double a_u = 0.001 * static_cast<double>(n % 2000) - 1.0;
    Frame frame = make_input_frame(a_u, n);
    if (n % 100 == 7) frame.data[3] ^= 0x40;  // corrupted: bad CRC (its slot is held)
    const CheckResult result = checker.check(frame, n * 1000000u);
    if (result.verdict == FrameVerdict::accepted) {
      ++accepted;
      sum += physical<double>(kSeatInput.signals[0], result.payload.words[0]);
    } else {
      ++refused;
    }
    Payload out;
    out.sample_counter = static_cast<std::uint16_t>(n);
    out.words[0] = quantise(kSeatMotion.signals[0], static_cast<float>(a_u)).word;
    const Frame output = make_frame(kSeatMotion, out);
    if (!crc_ok(kSeatMotion, output.data)) ++refused;
  }
  const stickslip::test::AllocationCount count = stickslip::test::stop_counting_allocations();
  // (test_allocation_counter.cpp proves the counter sees real allocations)
  LONGS_EQUAL(0, count.calls);
  LONGS_EQUAL(9900, accepted);
  LONGS_EQUAL(100, refused);
  LONGS_EQUAL(100, checker.counters().bad_crc);
  LONGS_EQUAL(100, checker.counters().lost);
  CHECK(sum != 0.0);
}
