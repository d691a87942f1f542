// Replays a candump log through the node exactly as a CAN driver would deliver it, for a board
// that has files (the host, or QEMU through semihosting). Files of frame records
// (kFrameRecordBytes each: identifier as 4 bytes little endian, length, Frame::flags, 2 zero
// bytes, 8 data bytes; tools/qemu-compare.sh writes the input from the log):
//   stickslip-input.bin   the frames received, in the log's order;
//   stickslip-frames.bin  every frame the node sent;
//   stickslip-records.bin one stickslip_node_record() per received frame that stepped the seat
//                         (the state after its last sample).
// The same bytes from the host build and the target build mean the same bits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "node.hpp"

inline constexpr std::size_t kFrameRecordBytes = 16;

// One halfword of a classic frame's data, i even, zero from byte `length` on. Both ends are
// 2-aligned (Frame::data; a record's data at byte 8): ARMv6-M has no unaligned word access, and
// a copy whose alignment the compiler cannot see is a memcpy call there.
[[gnu::always_inline]] inline void move_halfword(std::uint8_t* to, const std::uint8_t* from, int i,
                                                 std::uint8_t length) noexcept {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "a halfword's first byte is its low");
  std::uint16_t halfword = 0;
  std::memcpy(&halfword, __builtin_assume_aligned(from + i, 2), sizeof halfword);
  if (i + 1 >= length) halfword = static_cast<std::uint16_t>(i >= length ? 0u : halfword & 0x00FFu);
  std::memcpy(__builtin_assume_aligned(to + i, 2), &halfword, sizeof halfword);
}

// Moves a classic frame's 8 data bytes as four halfwords, as a CAN controller's mailbox takes
// them, with the bytes from `length` on zero (a byte loop costs about 90 ARMv6-M instructions a
// frame). Unrolled, with the zeros masked per halfword: a loop over the tail would be a memset
// call of variable length, which the firmware's static bound (tools/elf-wcet.py) refuses.
[[gnu::always_inline]] inline void copy_classic_data(std::uint8_t* to, const std::uint8_t* from,
                                                     std::uint8_t length) noexcept {
  static_assert(
      offsetof(stickslip::can::Frame, data) % 2 == 0 && alignof(stickslip::can::Frame) % 2 == 0,
      "Frame::data starts on a halfword");
  static_assert(stickslip::can::kClassicMaxLength == 8, "four halfwords");
  move_halfword(to, from, 0, length);
  move_halfword(to, from, 2, length);
  move_halfword(to, from, 4, length);
  move_halfword(to, from, 6, length);
}

// The receive mailbox's read: the fields a frame from Replay::next_frame() has (a classic
// frame's; its length is at most 8), not the 80 bytes of Frame's CAN FD room.
inline void read_mailbox(stickslip::can::Frame& to, const stickslip::can::Frame& from) noexcept {
  to.id = from.id;
  to.length = from.length;
  to.flags = from.flags;
  copy_classic_data(to.data, from.data, from.length);
}

// Read: `read(buffer, capacity)` returns the bytes read (0 at the end). Write:
// `write(file, bytes, count)` writes them all to file 0 (frames) or 1 (records).
template <typename Read, typename Write>
class Replay {
 public:
  Replay(Read read, Write write) : read_(read), write_(write) {}

  // Pops the next input frame; false at the end of the log.
  bool next_frame(stickslip::can::Frame* frame) {
    if (next_ + kFrameRecordBytes > filled_) {
      // Refill, keeping a partial record.
      const std::size_t kept = filled_ - next_;
      for (std::size_t i = 0; i < kept; ++i) input_[i] = input_[next_ + i];
      filled_ = kept + read_(input_ + kept, sizeof input_ - kept);
      next_ = 0;
      if (filled_ < kFrameRecordBytes) return false;
    }
    const std::uint8_t* r = input_ + next_;
    frame->id = static_cast<std::uint32_t>(r[0]) | static_cast<std::uint32_t>(r[1]) << 8 |
                static_cast<std::uint32_t>(r[2]) << 16 | static_cast<std::uint32_t>(r[3]) << 24;
    frame->length = r[4] > 8 ? 8 : r[4];
    frame->flags = r[5];
    for (int i = 0; i < 8; ++i) frame->data[i] = r[8 + i];
    next_ += kFrameRecordBytes;
    return true;
  }
  // Appends a frame the node sent.
  void sent(const stickslip::can::Frame& frame) {
    if (frames_used_ + kFrameRecordBytes > sizeof frames_) flush_frames();
    std::uint8_t* r = frames_ + frames_used_;
    // Little-endian words (both the host and the Cortex-M targets are little-endian).
    static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
                  "the record's words are little-endian");
    const std::uint32_t words[2] = {frame.id, frame.length | std::uint32_t{frame.flags} << 8};
    std::memcpy(__builtin_assume_aligned(r, 4), words, sizeof words);
    copy_classic_data(r + 8, frame.data, frame.length);
    frames_used_ += kFrameRecordBytes;
  }
  // After a received frame whose samples the node stepped: appends the record of its last step
  // (outside the receive interrupt, so that the instruction count is the node's alone).
  void sampled() {
    if (records_used_ + kNodeRecordBytes > sizeof records_) flush_records();
    stickslip_node_record(records_ + records_used_);
    records_used_ += kNodeRecordBytes;
  }
  // Between interrupts: writes the frames out once half the buffer is used (a frame that ends a
  // long gap sends up to 2 (max_gap + 1) frames, which the other half holds).
  void flush_if_half_full() {
    if (frames_used_ * 2 >= sizeof frames_) flush_frames();
  }
  void flush() {
    flush_frames();
    flush_records();
  }

 private:
  void flush_frames() {
    if (frames_used_ != 0) write_(0, frames_, frames_used_);
    frames_used_ = 0;
  }
  void flush_records() {
    if (records_used_ != 0) write_(1, records_, records_used_);
    records_used_ = 0;
  }

  Read read_;
  Write write_;
  std::uint8_t input_[kFrameRecordBytes * 16] = {};
  std::size_t filled_ = 0, next_ = 0;
  alignas(4) std::uint8_t frames_[kFrameRecordBytes * 512] = {};
  std::size_t frames_used_ = 0;
  std::uint8_t records_[kNodeRecordBytes * 16] = {};
  std::size_t records_used_ = 0;
};
