// CAN database (.dbc) files as vehicle makers publish them: messages (BO_), their signals (SG_)
// with either byte order, signedness, factor, offset, range and unit, comments (CM_) and value
// tables (VAL_). Multiplexed signals are refused (the line is named). Other sections (BU_, BA_,
// BA_DEF_, NS_, ...) are read over. docs/RECORDINGS.md has the details.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace stickslip::host {

enum class ByteOrder {
  kIntel,     // @1: little endian; the start bit is the least significant bit
  kMotorola,  // @0: big endian; the start bit is the most significant bit, numbered as DBC
              //     files do (bit 7 of byte 0 is 7, bit 0 of byte 1 is 8)
};

// physical = raw * factor + offset, computed as one correctly rounded division where the decimal
// factor and offset allow it (dbc.cpp): the double nearest to the exact decimal result.
struct DbcScale {
  double factor = 1.0;
  double offset = 0.0;
  // Exact form: physical = (raw * numerator_per_raw + numerator_offset) / denominator.
  bool exact = false;
  std::int64_t numerator_per_raw = 1;
  std::int64_t numerator_offset = 0;
  double denominator = 1.0;
};

struct DbcSignal {
  std::string name;
  unsigned start_bit = 0;
  unsigned length_bits = 1;  // 1..64
  ByteOrder byte_order = ByteOrder::kIntel;
  bool is_signed = false;
  DbcScale scale;
  double minimum = 0.0;
  double maximum = 0.0;
  std::string unit;
  std::vector<std::string> receivers;
  std::string comment;
  std::vector<std::pair<std::int64_t, std::string>> value_names;  // VAL_
  std::size_t line = 0;                                           // where SG_ is, 1-based
  unsigned bytes_needed = 0;  // the frame must hold this many bytes to carry the signal
};

struct DbcMessage {
  std::uint32_t id = 0;  // without the DBC's extended flag (bit 31)
  bool extended = false;
  std::string name;
  unsigned dlc = 0;
  std::string sender;
  std::string comment;
  std::vector<DbcSignal> signals;
  std::size_t line = 0;

  const DbcSignal* find_signal(std::string_view name) const;
};

struct Dbc {
  std::string path;
  std::vector<DbcMessage> messages;

  const DbcMessage* find_message(std::string_view name) const;
  const DbcMessage* find_message(std::uint32_t id, bool extended) const;
};

// Throws HostError "FILE:LINE: problem" for a statement it cannot read or refuses.
Dbc read_dbc(const std::string& path);
Dbc parse_dbc(std::string_view text, const std::string& path);

// The raw integer of `signal` in `data` (sign-extended when signed); nullopt when the frame is
// too short to hold it.
std::optional<std::int64_t> raw_value(const DbcSignal& signal, const std::uint8_t* data,
                                      std::size_t length) noexcept;
// The physical value (in the signal's unit) of a raw value.
double physical_value(const DbcSignal& signal, std::int64_t raw) noexcept;
// Both: the value the frame carries, or nullopt when it is too short.
std::optional<double> decode_signal(const DbcSignal& signal, const std::uint8_t* data,
                                    std::size_t length) noexcept;

}  // namespace stickslip::host
