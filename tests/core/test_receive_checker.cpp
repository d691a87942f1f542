// ReceiveChecker::check() into a caller's result (what EcuNode keeps as a member) against the
// value it returns: every field is written whatever the result held before.
#include <cstdint>
#include <cstring>
#include <random>

#include "CppUTest/TestHarness.h"
#include "stickslip/can/codec.hpp"
#include "stickslip/can/receive_checker.hpp"

using namespace stickslip;

namespace {

bool same(const can::CheckResult& a, const can::CheckResult& b) {
  return a.verdict == b.verdict && a.lost_samples == b.lost_samples &&
         a.skipped_samples == b.skipped_samples && a.resync == b.resync && a.hold == b.hold &&
         a.payload.sample_counter == b.payload.sample_counter &&
         a.payload.alive_counter == b.payload.alive_counter && a.payload.flags == b.payload.flags &&
         a.payload.words[0] == b.payload.words[0] && a.payload.words[1] == b.payload.words[1];
}

// A SeatInput frame with the given counters and a_u word (the not-available word included).
can::Frame input_frame(std::uint16_t counter, std::uint8_t alive, std::uint16_t word) {
  can::Payload payload;
  payload.sample_counter = counter;
  payload.alive_counter = static_cast<std::uint8_t>(alive & 0x0Fu);
  payload.words[0] = word;
  payload.words[1] = static_cast<std::uint16_t>(can::kSignedNotAvailable);
  return can::make_frame(can::kSeatInput, payload);
}

}  // namespace

TEST_GROUP(ReceiveCheckerResult){};

TEST(ReceiveCheckerResult, CheckingIntoAReusedResultWritesEveryFieldAsTheReturnedOne) {
  can::CheckerConfig config;
  config.max_gap = 10;
  can::ReceiveChecker returning(config), in_place(config);
  // Stale bytes in every field before the first frame; then each frame's result stays in it.
  can::CheckResult reused;
  std::memset(static_cast<void*>(&reused), 0xA5, sizeof reused);
  std::mt19937 random(20261128u);
  std::uint16_t counter = 0;
  std::uint8_t alive = 0;
  // Frames whose result sets a field that the next one must clear, counted so that the run is
  // known to reach them.
  int lost = 0, skipped = 0, resyncs = 0, holds = 0, refused = 0;
  for (int n = 0; n < 20000; ++n) {
    const std::uint32_t r = random();
    const std::uint32_t kind = r % 16u;
    std::uint16_t step = 1;
    if (kind == 0) step = static_cast<std::uint16_t>(2 + (r >> 4) % 9);          // lost, held
    if (kind == 1) step = static_cast<std::uint16_t>(12 + (r >> 4) % 50);        // beyond the gap
    if (kind == 2) step = 0;                                                     // duplicate
    if (kind == 3) step = static_cast<std::uint16_t>(0x8000u + (r >> 4) % 100);  // behind
    const auto next = static_cast<std::uint16_t>(counter + step);
    const auto next_alive = static_cast<std::uint8_t>((alive + step) & 0x0Fu);
    const bool unavailable = kind == 4;
    can::Frame frame =
        input_frame(next, kind == 5 ? static_cast<std::uint8_t>(next_alive + 1u) : next_alive,
                    unavailable ? static_cast<std::uint16_t>(can::kSignedNotAvailable)
                                : static_cast<std::uint16_t>(r >> 16));
    if (kind == 6) frame.data[0] ^= 0x01u;  // bad CRC
    if (kind == 7) frame.length = 7;
    if (kind == 8) frame.flags = can::kRemote;
    const std::uint64_t now_ns = static_cast<std::uint64_t>(n) * 1000000u;
    const can::CheckResult expected = returning.check(frame, now_ns);
    in_place.check(frame, now_ns, reused);
    CHECK_TEXT(same(expected, reused), "frame differs");
    const bool moved = expected.verdict == can::FrameVerdict::accepted ||
                       expected.verdict == can::FrameVerdict::invalid_signal;
    if (moved) {  // the sender's counters as the checker now expects them
      counter = next;
      alive = next_alive;
    }
    lost += expected.lost_samples > 0;
    skipped += expected.skipped_samples > 0;
    resyncs += expected.resync;
    holds += expected.hold;
    refused += !moved;
  }
  CHECK(lost > 100 && skipped > 100 && resyncs > 100 && holds > 100 && refused > 1000);
  LONGS_EQUAL(returning.counters().faults(), in_place.counters().faults());
  LONGS_EQUAL(returning.counters().accepted, in_place.counters().accepted);
}
