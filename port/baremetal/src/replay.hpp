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

#include "node.hpp"

inline constexpr std::size_t kFrameRecordBytes = 16;

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
    for (int i = 0; i < 4; ++i) r[i] = static_cast<std::uint8_t>(frame.id >> (8 * i));
    r[4] = frame.length;
    r[5] = frame.flags;
    r[6] = r[7] = 0;
    for (int i = 0; i < 8; ++i) r[8 + i] = i < frame.length ? frame.data[i] : 0;
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
  std::uint8_t frames_[kFrameRecordBytes * 512] = {};
  std::size_t frames_used_ = 0;
  std::uint8_t records_[kNodeRecordBytes * 16] = {};
  std::size_t records_used_ = 0;
};
