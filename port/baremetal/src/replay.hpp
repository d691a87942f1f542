// Replays a recording through the node exactly as a CAN driver would deliver it, for a board
// that has files (the host, or QEMU through semihosting): input = the int16 a_u payloads (mm/s^2,
// little endian, 2 bytes per sample), output = one stickslip_node_record() per step. The same
// bytes from the host build and the target build mean the same bits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "node.hpp"

// A frame source and sink over byte streams: `read(buffer, capacity)` returns the bytes read
// (0 at the end), `write(bytes, count)` writes them all.
template <typename Read, typename Write>
class Replay {
 public:
  Replay(Read read, Write write) : read_(read), write_(write) {}

  // Pops the next input frame; false at the end of the recording.
  bool next_frame(stickslip::can::Frame* frame) {
    if (next_ + 2 > filled_) {
      // Refill, keeping an odd byte.
      const std::size_t kept = filled_ - next_;
      for (std::size_t i = 0; i < kept; ++i) input_[i] = input_[next_ + i];
      filled_ = kept + read_(input_ + kept, sizeof input_ - kept);
      next_ = 0;
      if (filled_ < 2) return false;
    }
    frame->id = kNodeInputId;
    frame->length = 2;
    frame->flags = 0;
    frame->data[0] = input_[next_];
    frame->data[1] = input_[next_ + 1];
    next_ += 2;
    return true;
  }
  // After each step: appends the node's record.
  void record() {
    if (used_ + kNodeRecordBytes > sizeof output_) flush();
    stickslip_node_record(output_ + used_);
    used_ += kNodeRecordBytes;
  }
  void flush() {
    if (used_ != 0) write_(output_, used_);
    used_ = 0;
  }

 private:
  Read read_;
  Write write_;
  std::uint8_t input_[256] = {};
  std::size_t filled_ = 0, next_ = 0;
  std::uint8_t output_[kNodeRecordBytes * 32] = {};
  std::size_t used_ = 0;
};
