// The CAN frame decoder and the receive checker on an arbitrary stream of frames: every frame gets
// exactly one verdict, the counters add up to the frames checked, and nothing refused or corrupt
// ever comes out as an accepted sample (an accepted frame is a whole classic SeatInput frame with
// a valid CRC, an available a_u and a counter that moved forward by at most max_gap + 1, unless
// the checker says resync).
//
// Layout: two bytes configure the checker (max_gap, silence timeout); then per frame a kind byte:
//   kind % 4 == 0   raw frame: id, flags, length and up to 64 data bytes from the input
//   otherwise       a valid SeatInput frame made with the codec: a counter step, an a_u word and
//                   flags from the input, then an optional corruption of one byte (so the
//                   sequence logic is reached without the fuzzer having to guess CRCs)
// plus a time step (0 .. 2^24 us) before each frame and sometimes a silence check.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstring>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/receive_checker.hpp"

namespace {

using namespace stickslip::can;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

std::uint64_t verdict_sum(const FaultCounters& c) {
  return c.accepted + c.ignored_output + c.duplicate + c.out_of_order + c.bad_crc + c.wrong_length +
         c.foreign_frames + c.can_fd + c.error_frame + c.remote_frame + c.alive_mismatch +
         c.invalid_signal;
}

Frame raw_frame(FuzzedDataProvider& in) {
  Frame frame;
  frame.id = in.ConsumeIntegral<std::uint32_t>() & kExtendedIdMask;
  frame.flags = in.ConsumeIntegral<std::uint8_t>() & 0x0Fu;
  // Ids near the node's own, so the id checks see more than "unknown".
  if (in.ConsumeBool()) frame.id = kSeatInput.id + (frame.id & 0x3u) * 0x40u;
  frame.length = in.ConsumeIntegralInRange<std::uint8_t>(0, kFdMaxLength);
  const std::size_t available = in.ConsumeData(frame.data, frame.length);
  std::memset(frame.data + available, 0, sizeof frame.data - available);
  return frame;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  CheckerConfig config;
  config.max_gap = in.ConsumeIntegral<std::uint8_t>();
  config.silence_timeout_ns = 1000ull * (1u + in.ConsumeIntegral<std::uint16_t>());
  ReceiveChecker checker(config);
  checker.restart(0);

  std::uint64_t now_ns = 0;
  std::uint64_t frames = 0;
  std::uint64_t lost = 0, held = 0, skipped = 0, resyncs = 0;  // recounted from the verdicts
  std::uint16_t counter = 0;
  bool have_last = false;
  std::uint16_t last_accepted_counter = 0;
  while (in.remaining_bytes() > 0) {
    const std::uint8_t kind = in.ConsumeIntegral<std::uint8_t>();
    Frame frame;
    if (kind % 4 == 0) {
      frame = raw_frame(in);
    } else {
      counter = static_cast<std::uint16_t>(counter + in.ConsumeIntegralInRange<int>(-3, 300));
      Payload payload;
      payload.sample_counter = counter;
      payload.alive_counter = static_cast<std::uint8_t>(
          (kind & 0x10u) != 0 ? in.ConsumeIntegral<std::uint8_t>() & 0x0Fu : counter & 0x0Fu);
      payload.flags = in.ConsumeIntegral<std::uint8_t>() & 0x0Fu;
      payload.words[0] = in.ConsumeIntegral<std::uint16_t>();
      payload.words[1] = in.ConsumeIntegral<std::uint16_t>();
      frame = make_frame(kSeatInput, payload);
      // The codec's own round trip: what encode wrote, decode reads back.
      const Payload back = decode_payload(frame.data);
      check(back.sample_counter == payload.sample_counter &&
            back.alive_counter == payload.alive_counter && back.flags == payload.flags &&
            back.words[0] == payload.words[0] && back.words[1] == payload.words[1]);
      check(crc_ok(kSeatInput, frame.data));
      if ((kind & 0x20u) != 0) {  // corrupt one byte (and maybe the length)
        const std::uint8_t at = in.ConsumeIntegralInRange<std::uint8_t>(0, kPayloadLength - 1);
        frame.data[at] ^= in.ConsumeIntegralInRange<std::uint8_t>(1, 255);
        if ((kind & 0x40u) != 0) frame.length = in.ConsumeIntegralInRange<std::uint8_t>(0, 8);
      }
    }
    now_ns += 1000ull * in.ConsumeIntegralInRange<std::uint32_t>(0, 1u << 24);
    if ((kind & 0x80u) != 0) checker.check_silence(now_ns);

    const CheckResult result = checker.check(frame, now_ns);
    ++frames;
    const FaultCounters& c = checker.counters();
    check(c.frames == frames);
    check(verdict_sum(c) == frames);
    if (result.verdict == FrameVerdict::accepted ||
        result.verdict == FrameVerdict::invalid_signal) {
      lost += result.lost_samples;
      held += result.lost_samples + (result.hold ? 1u : 0u);
      skipped += result.skipped_samples;
      resyncs += result.resync ? 1u : 0u;
    }
    check(c.lost == lost && c.held_samples == held && c.resync == resyncs && c.skipped == skipped);

    if (result.verdict == FrameVerdict::accepted) {
      // Only a whole, intact SeatInput frame with a sample in it is ever used.
      check(frame.id == kSeatInput.id && frame.flags == 0 && frame.length == kPayloadLength);
      check(crc_ok(kSeatInput, frame.data));
      check(!not_available(kSeatInput.signals[0], result.payload.words[0]));
      const Payload decoded = decode_payload(frame.data);
      check(decoded.sample_counter == result.payload.sample_counter &&
            decoded.words[0] == result.payload.words[0]);
      if (have_last) {
        const auto d =
            static_cast<std::uint16_t>(result.payload.sample_counter - last_accepted_counter);
        if (!result.resync) {
          check(d >= 1 && d <= config.max_gap + 1u);
          check(result.lost_samples == d - 1u && result.skipped_samples == 0);
        } else if (d < 0x8000u) {  // a forward resync: the frames between are skipped
          check(d > config.max_gap + 1u && result.skipped_samples == d - 1u);
          check(result.lost_samples == 0);
        } else {  // a restarted stream: nothing lost, nothing skipped
          check(result.lost_samples == 0 && result.skipped_samples == 0);
        }
      }
      check(result.lost_samples <= config.max_gap);
      have_last = true;
      last_accepted_counter = result.payload.sample_counter;
    } else if (result.verdict == FrameVerdict::invalid_signal && result.hold) {
      have_last = true;  // the counter moved on without a sample
      last_accepted_counter = result.payload.sample_counter;
    } else {
      check(result.lost_samples == 0 && result.skipped_samples == 0 && !result.resync);
    }
  }
  return 0;
}
