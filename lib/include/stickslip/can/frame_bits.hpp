// Bits a classic CAN frame takes on the wire, for the bus load (docs/CAN.md, "Bus load").
// Allocation-free, noexcept, standard headers only.
//
// Exact count (ISO 11898-1): SOF, identifier (11 bits; or 11 + SRR + IDE + 18), RTR, IDE + r0
// (standard; r1 + r0 extended), DLC, data (none for a remote frame), CRC-15 over SOF..data; a
// stuff bit after every 5 equal bits from SOF to the end of the CRC (the stuff bit starts the
// next run); then CRC delimiter, ACK slot, ACK delimiter, 7 EOF and 3 intermission bits.
// Worst case: can-utils' canframelen.h formula (CFL_WORSTCASE, what canbusload uses without -e):
// 55 + 10 n bits (11-bit id) and 80 + 10 n (29-bit id) for n data bytes.
#pragma once

#include <cstdint>

#include "stickslip/can/frame.hpp"

namespace stickslip::can {

namespace detail {

// Feeds bits MSB first through the CRC-15 (x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1,
// 0x4599, initial 0) and the stuffing rule, counting the stuffed bits.
class StuffCounter {
 public:
  void bits(std::uint32_t value, int count, bool crc = true) noexcept {
    for (int i = count - 1; i >= 0; --i) bit(((value >> i) & 1u) != 0, crc);
  }
  std::uint16_t crc() const noexcept { return crc_; }
  unsigned stuffed() const noexcept { return stuffed_; }
  unsigned sent() const noexcept { return sent_; }

 private:
  void bit(bool level, bool crc) noexcept {
    if (crc) {
      const bool top = ((crc_ >> 14) & 1u) != 0;
      crc_ = static_cast<std::uint16_t>((crc_ << 1) & 0x7FFFu);
      if (top != level) crc_ ^= 0x4599u;
    }
    ++sent_;
    run_ = (sent_ > 1 && level == last_) ? run_ + 1 : 1;
    last_ = level;
    if (run_ == 5) {  // the stuff bit: the opposite level, the first of the next run
      ++stuffed_;
      ++sent_;
      last_ = !level;
      run_ = 1;
    }
  }

  std::uint16_t crc_ = 0;
  unsigned stuffed_ = 0;
  unsigned sent_ = 0;
  unsigned run_ = 0;
  bool last_ = false;
};

}  // namespace detail

// Bits after the CRC sequence, never stuffed: CRC delimiter, ACK slot and delimiter, EOF, IFS.
inline constexpr unsigned kFrameTrailerBits = 1 + 1 + 1 + 7 + 3;

// The data bytes a classic frame carries on the wire (a remote frame: none).
inline unsigned wire_data_bytes(const Frame& frame) noexcept {
  if (frame.flags & kRemote) return 0;
  return frame.length > 8 ? 8u : frame.length;
}

// The exact number of bits of a classic data or remote frame, stuff bits included.
inline unsigned frame_bits_exact(const Frame& frame) noexcept {
  detail::StuffCounter wire;
  const bool extended = (frame.flags & kExtendedId) != 0;
  const unsigned remote = (frame.flags & kRemote) ? 1u : 0u;
  const unsigned dlc = frame.length > 15 ? 15u : frame.length;
  wire.bits(0, 1);  // SOF
  if (extended) {
    wire.bits((frame.id >> 18) & 0x7FFu, 11);
    wire.bits(0x3u, 2);  // SRR, IDE: recessive
    wire.bits(frame.id & 0x3FFFFu, 18);
    wire.bits(remote, 1);
    wire.bits(0, 2);  // r1, r0
  } else {
    wire.bits(frame.id & 0x7FFu, 11);
    wire.bits(remote, 1);
    wire.bits(0, 2);  // IDE, r0
  }
  wire.bits(dlc, 4);
  for (unsigned n = 0; n < wire_data_bytes(frame); ++n) wire.bits(frame.data[n], 8);
  wire.bits(wire.crc(), 15, false);
  return wire.sent() + kFrameTrailerBits;
}

// can-utils' worst case (see above).
inline unsigned frame_bits_worst_case(const Frame& frame) noexcept {
  const unsigned n = wire_data_bytes(frame);
  return ((frame.flags & kExtendedId) ? 80u : 55u) + 10u * n;
}

// The same frame without any stuff bit: 47 + 8 n (11-bit id), 67 + 8 n (29-bit id).
inline unsigned frame_bits_unstuffed(const Frame& frame) noexcept {
  return ((frame.flags & kExtendedId) ? 67u : 47u) + 8u * wire_data_bytes(frame);
}

}  // namespace stickslip::can
