// One CAN frame as the codec, the ports and the host tools pass it around. Large enough for a
// CAN FD frame so that a port can report what it really received (the node refuses FD frames and
// counts them; it never truncates one into a classic frame).
#pragma once

#include <cstdint>

namespace stickslip::can {

inline constexpr std::uint32_t kStandardIdMask = 0x7FFu;       // 11-bit identifier
inline constexpr std::uint32_t kExtendedIdMask = 0x1FFFFFFFu;  // 29-bit identifier
inline constexpr std::uint8_t kClassicMaxLength = 8;           // bytes
inline constexpr std::uint8_t kFdMaxLength = 64;               // bytes

// Frame kinds other than a classic data frame with an 11-bit id, as bits in Frame::flags.
enum FrameFlag : std::uint8_t {
  kExtendedId = 1u << 0,  // 29-bit identifier
  kRemote = 1u << 1,      // remote transmission request (no data)
  kErrorFrame = 1u << 2,  // error frame reported by the controller/driver
  kFd = 1u << 3,          // CAN FD frame (length may be up to 64)
};

struct Frame {
  std::uint32_t id = 0;     // identifier, 11 bits unless flags has kExtendedId
  std::uint8_t length = 0;  // data bytes: 0..8 classic, 0..64 FD (the DLC as a byte count)
  std::uint8_t flags = 0;   // FrameFlag bits
  std::uint8_t data[kFdMaxLength] = {};
  std::uint64_t timestamp_ns = 0;  // receive time from the port (0: unknown); not part of the frame
};

}  // namespace stickslip::can
