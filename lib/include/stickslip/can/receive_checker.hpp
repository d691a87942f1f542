// Classifies every frame that reaches the ECU and counts each kind; decides which samples the
// node may use. Allocation-free, noexcept; the caller supplies the time (any monotonic clock in
// nanoseconds), so the checker itself has no clock.
//
// Order of the checks (the first that fails names the fault): error frame, remote frame, CAN FD,
// identifier (one of the node's own output messages is ignored_output; any other id, or an
// extended id, is a foreign frame: another node's traffic, counted apart, not a fault),
// length != 8, CRC, then the counters. With e2e off (a plain sensor that sends no counters and
// no CRC) the CRC and counter checks are skipped: every SeatInput frame is the next sample.
//
// Counter and gap policy (docs/CAN.md): with d = (counter - last accepted counter) mod 2^16,
//   d == 0                    duplicate      refused
//   d >= 2^15                 out_of_order   refused (older than the last accepted frame)
//   1 <= d <= max_gap + 1     accepted; d - 1 samples were lost: the node holds the last good
//                             sample for each of them (time never slips), flags them as held
//   max_gap + 1 < d < 2^15    accepted as a resync (counted): the stream continues with this
//                             sample, the lost time is not filled in; the d - 1 frames missing
//                             are counted as skipped (so lost + skipped + accepted +
//                             invalid_signal spans every counter from the first to the last)
//   kRestartRun frames in a row that are behind, with consecutive counters: the sender has
//                             restarted; the last of them is accepted as a resync
// The alive counter must have advanced by d mod 16 too, else alive_mismatch (refused). A frame
// whose a_u is the not-available code advances the counter but carries no sample: invalid_signal,
// the node holds the last sample for it. Nothing refused ever reaches the model.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/frame.hpp"

namespace stickslip::can {

enum class FrameVerdict : std::uint8_t {
  accepted,        // a sample to use (see CheckResult::lost_samples, resync)
  ignored_output,  // one of the node's own output messages (another node's outputs): not a fault
  duplicate,
  out_of_order,
  bad_crc,
  wrong_length,
  foreign_frame,  // an id the node does not own (other traffic on the bus): not a fault
  can_fd,
  error_frame,
  remote_frame,
  alive_mismatch,
  invalid_signal,  // a_u not available: counter advanced, no sample (the node holds)
};

constexpr const char* frame_verdict_name(FrameVerdict verdict) noexcept {
  switch (verdict) {
    case FrameVerdict::accepted:
      return "accepted";
    case FrameVerdict::ignored_output:
      return "ignored_output";
    case FrameVerdict::duplicate:
      return "duplicate";
    case FrameVerdict::out_of_order:
      return "out_of_order";
    case FrameVerdict::bad_crc:
      return "bad_crc";
    case FrameVerdict::wrong_length:
      return "wrong_length";
    case FrameVerdict::foreign_frame:
      return "foreign_frame";
    case FrameVerdict::can_fd:
      return "can_fd";
    case FrameVerdict::error_frame:
      return "error_frame";
    case FrameVerdict::remote_frame:
      return "remote_frame";
    case FrameVerdict::alive_mismatch:
      return "alive_mismatch";
    case FrameVerdict::invalid_signal:
      return "invalid_signal";
  }
  return "unknown";
}

struct FaultCounters {
  std::uint64_t frames = 0;          // every frame checked
  std::uint64_t accepted = 0;        // frames whose sample was used
  std::uint64_t ignored_output = 0;  // the node's own message ids seen on the bus
  std::uint64_t lost = 0;            // frames missing from the counter sequence (gaps <= max_gap)
  std::uint64_t duplicate = 0;
  std::uint64_t out_of_order = 0;
  std::uint64_t bad_crc = 0;
  std::uint64_t wrong_length = 0;
  std::uint64_t foreign_frames = 0;  // ids the node does not own, 29-bit ids: not faults
  std::uint64_t can_fd = 0;
  std::uint64_t error_frame = 0;
  std::uint64_t remote_frame = 0;
  std::uint64_t alive_mismatch = 0;
  std::uint64_t invalid_signal = 0;
  std::uint64_t resync = 0;            // gaps beyond max_gap (or an implausible jump)
  std::uint64_t skipped = 0;           // frames missing across forward resyncs (not filled in)
  std::uint64_t silence = 0;           // periods without an accepted frame beyond the timeout
  std::uint64_t held_samples = 0;      // samples the node filled in (lost + invalid_signal)
  std::uint64_t sender_saturated = 0;  // accepted frames whose sender clipped a_u

  // Frames refused or missing: everything but accepted, ignored_output and foreign_frames.
  std::uint64_t faults() const noexcept {
    return lost + duplicate + out_of_order + bad_crc + wrong_length + can_fd + error_frame +
           remote_frame + alive_mismatch + invalid_signal + resync + skipped + silence;
  }
};

struct CheckResult {
  FrameVerdict verdict = FrameVerdict::foreign_frame;
  std::uint16_t lost_samples = 0;     // accepted: samples lost just before this one (to be held)
  std::uint16_t skipped_samples = 0;  // accepted after a forward resync: samples not filled in
  bool resync = false;                // accepted after a gap beyond max_gap
  bool hold = false;                  // invalid_signal: the node holds the last sample for this one
  Payload payload;                    // accepted / invalid_signal: the decoded SeatInput fields
};

struct CheckerConfig {
  std::uint16_t max_gap = 100;                   // samples held at most per gap (0.1 s at 1 kHz)
  std::uint64_t silence_timeout_ns = 100000000;  // 0.1 s without an accepted frame: silence
  // false: the sender has no E2E protection (a plain sensor: a_u in bytes 4-5, bytes 0..3 not
  // checked); no CRC, alive or sample counter checks, every SeatInput frame is the next sample.
  bool e2e = true;
};

class ReceiveChecker {
 public:
  // Consecutive "behind" frames with consecutive counters that make a restarted stream.
  static constexpr std::uint8_t kRestartRun = 4;

  explicit ReceiveChecker(const CheckerConfig& config = CheckerConfig{}) noexcept
      : config_(config) {}

  // Forgets the stream (the next input frame is accepted as the first); `now_ns` starts the
  // silence clock. Counters are kept; clear them with reset_counters().
  void restart(std::uint64_t now_ns) noexcept {
    synced_ = false;
    silent_ = false;
    ooo_run_ = 0;
    last_activity_ns_ = now_ns;
  }
  void reset_counters() noexcept { counters_ = FaultCounters{}; }

  CheckResult check(const Frame& frame, std::uint64_t now_ns) noexcept {
    CheckResult result;
    check(frame, now_ns, result);
    return result;
  }
  // The same, written into `result` (every field): for a caller that keeps the result where it
  // lives (EcuNode, off the receive interrupt's stack), which would otherwise assign it from a
  // zeroed temporary (a memset and a memcpy call a frame on the Cortex-M builds).
  void check(const Frame& frame, std::uint64_t now_ns, CheckResult& result) noexcept {
    ++counters_.frames;
    result.verdict = classify(frame, config_.e2e);
    result.lost_samples = result.skipped_samples = 0;
    result.resync = result.hold = false;
    // Field by field: a struct assignment is a memset call on the Cortex-M0+ build.
    result.payload.sample_counter = 0;
    result.payload.alive_counter = result.payload.flags = 0;
    result.payload.words[0] = result.payload.words[1] = 0;
    if (result.verdict == FrameVerdict::accepted) sequence(frame, now_ns, result);
    count(result);
  }

  // Call when no frame arrived for a while: counts one silence per silent period (until the next
  // accepted frame) once the stream has started (waiting for the first frame is not a fault).
  // Returns true when this call started a silence.
  bool check_silence(std::uint64_t now_ns) noexcept {
    if (!synced_ || silent_ || now_ns - last_activity_ns_ <= config_.silence_timeout_ns)
      return false;
    silent_ = true;
    ++counters_.silence;
    return true;
  }

  const FaultCounters& counters() const noexcept { return counters_; }
  const CheckerConfig& config() const noexcept { return config_; }
  bool synced() const noexcept { return synced_; }
  bool silent() const noexcept { return silent_; }

 private:
  static bool is_output_id(std::uint32_t id) noexcept {
    for (const MessageSpec* message : kOutputMessages)
      if (message->id == id) return true;
    return false;
  }

  static FrameVerdict classify(const Frame& frame, bool e2e) noexcept {
    if (frame.flags & kErrorFrame) return FrameVerdict::error_frame;
    if (frame.flags & kRemote) return FrameVerdict::remote_frame;
    if (frame.flags & kFd) return FrameVerdict::can_fd;
    if (frame.flags & kExtendedId) return FrameVerdict::foreign_frame;
    if (frame.id != kSeatInput.id) {
      return is_output_id(frame.id) ? FrameVerdict::ignored_output : FrameVerdict::foreign_frame;
    }
    if (frame.length != kPayloadLength) return FrameVerdict::wrong_length;
    if (e2e && !crc_ok(kSeatInput, frame.data)) return FrameVerdict::bad_crc;
    return FrameVerdict::accepted;
  }

  void sequence(const Frame& frame, std::uint64_t now_ns, CheckResult& result) noexcept {
    result.payload = decode_payload(frame.data);
    if (!config_.e2e) {
      // No counters on the wire: the frame is the next sample (what the node numbers it by).
      result.payload.sample_counter = synced_ ? static_cast<std::uint16_t>(last_counter_ + 1u) : 0;
      result.payload.alive_counter = static_cast<std::uint8_t>((last_alive_ + 1u) & 0x0Fu);
      result.payload.flags = 0;
    }
    const Payload& p = result.payload;
    const bool available = !not_available(kSeatInput.signals[0], p.words[0]);
    if (!synced_ && !available) {  // nothing to hold yet, and no counter to trust
      result.verdict = FrameVerdict::invalid_signal;
      return;
    }
    if (synced_) {
      const auto d = static_cast<std::uint16_t>(p.sample_counter - last_counter_);
      if (d == 0) {
        result.verdict = FrameVerdict::duplicate;
        return;
      }
      if (d >= 0x8000u) {
        // A sender that restarted (or a corrupted frame that passed the CRC with a counter far
        // ahead) would lock the stream out for up to 2^15 frames: a run of kRestartRun
        // consecutive counters, all "behind", is taken as a restarted stream (a resync).
        ooo_run_ = (ooo_run_ > 0 && p.sample_counter == static_cast<std::uint16_t>(ooo_last_ + 1u))
                       ? static_cast<std::uint8_t>(ooo_run_ + 1u)
                       : std::uint8_t{1};
        ooo_last_ = p.sample_counter;
        if (ooo_run_ < kRestartRun) {
          result.verdict = FrameVerdict::out_of_order;
          return;
        }
        result.resync = true;
      } else if (((last_alive_ + d) & 0x0Fu) != p.alive_counter) {
        result.verdict = FrameVerdict::alive_mismatch;
        return;
      }
      if (result.resync) {
        // restarted stream: nothing to hold
      } else if (d > static_cast<unsigned>(config_.max_gap) + 1u) {
        result.resync = true;
        result.skipped_samples = static_cast<std::uint16_t>(d - 1u);
      } else {
        result.lost_samples = static_cast<std::uint16_t>(d - 1u);
      }
    }
    synced_ = true;
    ooo_run_ = 0;
    last_counter_ = p.sample_counter;
    last_alive_ = p.alive_counter;
    last_activity_ns_ = now_ns;
    silent_ = false;
    if (!available) {
      result.verdict = FrameVerdict::invalid_signal;
      result.hold = true;
    }
  }

  // Each verdict's counter, in FrameVerdict's order: a table rather than a switch, which may
  // compile to a jump table that the firmware's static bound (tools/elf-wcet.py) cannot follow.
  static constexpr std::uint64_t FaultCounters::*kVerdictCounters[] = {
      &FaultCounters::accepted,       &FaultCounters::ignored_output,
      &FaultCounters::duplicate,      &FaultCounters::out_of_order,
      &FaultCounters::bad_crc,        &FaultCounters::wrong_length,
      &FaultCounters::foreign_frames, &FaultCounters::can_fd,
      &FaultCounters::error_frame,    &FaultCounters::remote_frame,
      &FaultCounters::alive_mismatch, &FaultCounters::invalid_signal,
  };
  static_assert(sizeof kVerdictCounters / sizeof kVerdictCounters[0] ==
                    static_cast<std::size_t>(FrameVerdict::invalid_signal) + 1,
                "one counter per verdict");

  void count(const CheckResult& result) noexcept {
    FaultCounters& c = counters_;
    ++(c.*kVerdictCounters[static_cast<std::size_t>(result.verdict)]);
    if (result.verdict == FrameVerdict::accepted && (result.payload.flags & kAuSaturated))
      ++c.sender_saturated;
    if (result.verdict == FrameVerdict::invalid_signal && result.hold) ++c.held_samples;
    if (result.verdict == FrameVerdict::accepted ||
        result.verdict == FrameVerdict::invalid_signal) {
      c.lost += result.lost_samples;
      c.held_samples += result.lost_samples;
      c.skipped += result.skipped_samples;
      if (result.resync) ++c.resync;
    }
  }

  CheckerConfig config_;
  FaultCounters counters_;
  bool synced_ = false;
  bool silent_ = false;
  std::uint16_t last_counter_ = 0;
  std::uint8_t last_alive_ = 0;
  std::uint64_t last_activity_ns_ = 0;
  std::uint16_t ooo_last_ = 0;  // counter of the last out-of-order frame
  std::uint8_t ooo_run_ = 0;    // consecutive out-of-order frames with consecutive counters
};

}  // namespace stickslip::can
