// CRC-8 SAE J1850 (polynomial 0x1D, initial value 0xFF, final XOR 0xFF, no reflection) as the
// AUTOSAR E2E profiles 1 and 11 use it: check value 0x4B over "123456789". One lookup per byte
// in a 256-byte table that the compiler computes from the bitwise definition.
#pragma once

#include <cstddef>
#include <cstdint>

namespace stickslip::can {

inline constexpr std::uint8_t kCrc8SaeJ1850Polynomial = 0x1D;
inline constexpr std::uint8_t kCrc8SaeJ1850Initial = 0xFF;
inline constexpr std::uint8_t kCrc8SaeJ1850FinalXor = 0xFF;

// Continues a CRC over more bytes. `register_value` is the raw register (before the final XOR):
// start with kCrc8SaeJ1850Initial, apply the final XOR once at the end.
namespace detail {

// The register after shifting one byte through the polynomial, MSB first (the bitwise definition).
constexpr std::uint8_t crc8_sae_j1850_byte(std::uint8_t register_value) noexcept {
  for (int bit = 0; bit < 8; ++bit) {
    register_value =
        (register_value & 0x80u)
            ? static_cast<std::uint8_t>((register_value << 1) ^ kCrc8SaeJ1850Polynomial)
            : static_cast<std::uint8_t>(register_value << 1);
  }
  return register_value;
}

struct Crc8Table {
  std::uint8_t entry[256];
};

constexpr Crc8Table make_crc8_sae_j1850_table() noexcept {
  Crc8Table table{};
  for (unsigned i = 0; i < 256; ++i)
    table.entry[i] = crc8_sae_j1850_byte(static_cast<std::uint8_t>(i));
  return table;
}

// Computed at compile time from the bitwise definition (256 bytes of flash): one lookup per
// byte instead of eight shifts, which is most of the node's receive check and output encoding on
// a Cortex-M (docs/EMBEDDED.md).
inline constexpr Crc8Table kCrc8SaeJ1850Table = make_crc8_sae_j1850_table();

}  // namespace detail

constexpr std::uint8_t crc8_sae_j1850_update(std::uint8_t register_value, const std::uint8_t* data,
                                             std::size_t size) noexcept {
  for (std::size_t i = 0; i < size; ++i)
    register_value = detail::kCrc8SaeJ1850Table.entry[register_value ^ data[i]];
  return register_value;
}

// The complete CRC of one buffer.
constexpr std::uint8_t crc8_sae_j1850(const std::uint8_t* data, std::size_t size) noexcept {
  return static_cast<std::uint8_t>(crc8_sae_j1850_update(kCrc8SaeJ1850Initial, data, size) ^
                                   kCrc8SaeJ1850FinalXor);
}

// E2E style frame protection: the CRC covers the 16-bit data ID (low byte, then high byte; not
// transmitted) followed by payload bytes 1..7. The data ID is different for every message, so a
// frame that arrives under the wrong identifier fails the check even if its bytes are intact.
// Unrolled: on a Cortex-M the loop's count and branch were half of each byte's instructions, and
// the node checks or encodes up to five frames per sample.
constexpr std::uint8_t e2e_crc(std::uint16_t data_id, const std::uint8_t* payload8) noexcept {
  const auto& table = detail::kCrc8SaeJ1850Table.entry;
  std::uint8_t reg = table[kCrc8SaeJ1850Initial ^ (data_id & 0xFFu)];
  reg = table[reg ^ (data_id >> 8)];
#pragma GCC unroll 7
  for (int i = 1; i < 8; ++i) reg = table[reg ^ payload8[i]];
  return static_cast<std::uint8_t>(reg ^ kCrc8SaeJ1850FinalXor);
}

}  // namespace stickslip::can
