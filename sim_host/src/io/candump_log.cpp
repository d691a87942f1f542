// can-utils' candump log format, as `candump -l` writes it and `canplayer` reads it:
//
//   (1700000000.123456) vcan0 123#DEADBEEF
//
//   line      := "(" seconds "." micro ")" " " interface " " frame [" " ("T" | "R")]
//   seconds   := 1 or more decimal digits;  micro := exactly 6 decimal digits
//   interface := 1..15 printable ASCII characters other than space (no control bytes, no NUL)
//   frame     := id3 "#" body | id8 "#" body
//   id3       := 3 hex digits, a standard id <= 7FF
//   id8       := 8 hex digits: an error frame when CAN_ERR_FLAG (20000000) is set (the id is
//                then the error class bits), else an extended id <= 1FFFFFFF
//   body      := "R" [dlc 0..8]              remote request (not for error frames)
//              | "#" flags data              CAN FD: one hex digit of flags (BRS/ESI), data
//                                            of 0..64 bytes with a valid FD length
//              | data                        classic: 0..8 bytes
//   data      := hex byte pairs, optionally separated by "." (as can-utils' lib.c accepts)
//
// This is the grammar of parse_canframe() in can-utils' lib.c, made strict: every character
// must belong to the record (lib.c ignores trailing garbage and odd digits), ids must fit their
// width, and FD lengths must be ones a DLC can express. The trailing direction flag is what
// newer candump versions append with -x. FD flags are read but not kept (can::Frame has no
// field for them); the writer writes 0. Hex digits are written in upper case, like candump.
#include "stickslip/host/io/candump_log.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"

namespace stickslip::host {
namespace {

constexpr std::uint32_t kErrorFlag = 0x20000000u;       // CAN_ERR_FLAG
constexpr std::uint32_t kErrorClassMask = 0x1FFFFFFFu;  // CAN_ERR_MASK
constexpr std::size_t kMaxInterfaceLength = 15;         // IFNAMSIZ - 1

// A log line is text: an interface name is printable ASCII without the separating space (a NUL or
// carriage return in it would not survive the write/read round trip).
bool interface_character(char c) {
  return c > ' ' && c < 0x7F;
}

bool is_fd_length(unsigned length) {
  return length <= 8 || length == 12 || length == 16 || length == 20 || length == 24 ||
         length == 32 || length == 48 || length == 64;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

class LineParser {
 public:
  LineParser(const std::string& path, std::size_t line_number, std::string_view text)
      : path_(path), line_number_(line_number), text_(text) {}

  LoggedFrame parse() {
    LoggedFrame logged;
    expect('(', "expected '(' opening the timestamp");
    const std::uint64_t seconds = decimal(0, "seconds of the timestamp");
    expect('.', "expected '.' in the timestamp (sec.usec)");
    const std::size_t micro_start = at_;
    const std::uint64_t micro = decimal(6, "microseconds of the timestamp (6 digits)");
    if (at_ - micro_start != 6) fail("the timestamp needs exactly 6 digits after '.'");
    expect(')', "expected ')' closing the timestamp");
    if (seconds > (UINT64_MAX / 1000u - micro) / 1000000u) fail("timestamp too large");
    logged.time_us = seconds * 1000000u + micro;
    expect(' ', "expected one space after the timestamp");
    const std::size_t name_start = at_;
    while (at_ < text_.size() && interface_character(text_[at_])) ++at_;
    if (at_ == name_start) fail("expected an interface name after the timestamp");
    if (at_ - name_start > kMaxInterfaceLength) fail("interface name longer than 15 characters");
    if (at_ < text_.size() && text_[at_] != ' ') {
      fail("interface name holds a character that is not printable ASCII (byte " +
           std::to_string(static_cast<unsigned char>(text_[at_])) + ")");
    }
    logged.interface = std::string(text_.substr(name_start, at_ - name_start));
    expect(' ', "expected one space after the interface name");
    parse_frame(logged.frame);
    if (at_ < text_.size()) {
      // Newer candump (-x) appends the direction.
      if (text_.substr(at_) != " T" && text_.substr(at_) != " R") {
        fail("unexpected '" + std::string(text_.substr(at_)) + "' after the frame");
      }
    }
    logged.frame.timestamp_ns = logged.time_us * 1000u;
    return logged;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw HostError(path_ + ":" + std::to_string(line_number_) + ": " + problem);
  }
  void expect(char c, const char* problem) {
    if (at_ >= text_.size() || text_[at_] != c) fail(problem);
    ++at_;
  }
  // Decimal digits (max_digits 0: any number, overflow checked).
  std::uint64_t decimal(std::size_t max_digits, const char* what) {
    std::uint64_t value = 0;
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9') {
      const auto digit = static_cast<std::uint64_t>(text_[at_] - '0');
      if (value > (UINT64_MAX - digit) / 10u) fail(std::string(what) + " too large");
      value = value * 10u + digit;
      ++at_;
      if (max_digits != 0 && at_ - start > max_digits) break;
    }
    if (at_ == start) fail(std::string("expected the ") + what);
    return value;
  }
  std::uint32_t hex_digits(std::size_t count) {
    std::uint32_t value = 0;
    for (std::size_t n = 0; n < count; ++n) {
      const int digit = hex_value(text_[at_ + n]);
      if (digit < 0)
        fail("'" + std::string(1, text_[at_ + n]) + "' is not a hex digit in the CAN id");
      value = (value << 4) | static_cast<std::uint32_t>(digit);
    }
    at_ += count;
    return value;
  }

  void parse_frame(can::Frame& frame) {
    const std::size_t hash = text_.find('#', at_);
    if (hash == std::string_view::npos) fail("expected ID#data (no '#')");
    const std::size_t id_digits = hash - at_;
    if (id_digits != 3 && id_digits != 8) {
      fail("the CAN id must have 3 (standard) or 8 (extended or error) hex digits, not " +
           std::to_string(id_digits));
    }
    const std::uint32_t id = hex_digits(id_digits);
    if (id_digits == 3) {
      if (id > can::kStandardIdMask) fail("standard id above 7FF");
      frame.id = id;
    } else if ((id & kErrorFlag) != 0) {
      if ((id & ~(kErrorFlag | kErrorClassMask)) != 0)
        fail("error frame id with bits above 0x3FFFFFFF");
      frame.id = id & kErrorClassMask;
      frame.flags = can::kErrorFrame;
    } else {
      if (id > can::kExtendedIdMask) fail("extended id above 1FFFFFFF");
      frame.id = id;
      frame.flags = can::kExtendedId;
    }
    ++at_;  // '#'
    const bool error_frame = (frame.flags & can::kErrorFrame) != 0;
    if (at_ < text_.size() && (text_[at_] == 'R' || text_[at_] == 'r')) {
      if (error_frame) fail("an error frame cannot be a remote request");
      ++at_;
      frame.flags |= can::kRemote;
      if (at_ < text_.size() && text_[at_] != ' ') {
        const int dlc = hex_value(text_[at_]);
        if (dlc < 0 || dlc > 8) fail("remote request DLC must be 0..8");
        frame.length = static_cast<std::uint8_t>(dlc);
        ++at_;
      }
      return;
    }
    std::size_t max_length = can::kClassicMaxLength;
    if (at_ < text_.size() && text_[at_] == '#') {
      if (error_frame) fail("an error frame cannot be a CAN FD frame");
      ++at_;
      if (at_ >= text_.size() || hex_value(text_[at_]) < 0)
        fail("CAN FD frame needs a flags hex digit after '##'");
      ++at_;  // flags (BRS/ESI) are not kept
      frame.flags |= can::kFd;
      max_length = can::kFdMaxLength;
    }
    std::size_t length = 0;
    while (at_ < text_.size() && text_[at_] != ' ') {
      // Optional separator between bytes (and after the FD flags, as candump -ta writes it).
      if (text_[at_] == '.' && (length > 0 || max_length == can::kFdMaxLength)) ++at_;
      if (at_ + 1 >= text_.size() || text_[at_ + 1] == ' ')
        fail("odd number of hex digits in the data");
      const int high = hex_value(text_[at_]);
      const int low = hex_value(text_[at_ + 1]);
      if (high < 0 || low < 0) fail("data must be hex byte pairs");
      if (length == max_length) {
        fail("more than " + std::to_string(max_length) + " data bytes");
      }
      frame.data[length++] = static_cast<std::uint8_t>((high << 4) | low);
      at_ += 2;
    }
    if ((frame.flags & can::kFd) != 0 && !is_fd_length(static_cast<unsigned>(length))) {
      fail("CAN FD length " + std::to_string(length) + " is not one a DLC can express");
    }
    frame.length = static_cast<std::uint8_t>(length);
  }

  const std::string& path_;
  std::size_t line_number_;
  std::string_view text_;
  std::size_t at_ = 0;
};

// The frame part of a record ("123#DEADBEEF"), or an error naming what is wrong.
std::string format_frame(const can::Frame& frame, const std::string& where) {
  char buffer[8 + 3 + 2 * can::kFdMaxLength + 1];
  int used = 0;
  const bool error_frame = (frame.flags & can::kErrorFrame) != 0;
  const bool extended = (frame.flags & can::kExtendedId) != 0;
  const bool remote = (frame.flags & can::kRemote) != 0;
  const bool fd = (frame.flags & can::kFd) != 0;
  if (error_frame) {
    if (extended || remote || fd || frame.id > kErrorClassMask ||
        frame.length > can::kClassicMaxLength) {
      throw HostError(where + ": invalid error frame");
    }
    used =
        std::snprintf(buffer, sizeof buffer, "%08X#", static_cast<unsigned>(frame.id | kErrorFlag));
  } else if (extended) {
    if (frame.id > can::kExtendedIdMask) throw HostError(where + ": extended id above 1FFFFFFF");
    used = std::snprintf(buffer, sizeof buffer, "%08X#", static_cast<unsigned>(frame.id));
  } else {
    if (frame.id > can::kStandardIdMask) throw HostError(where + ": standard id above 7FF");
    used = std::snprintf(buffer, sizeof buffer, "%03X#", static_cast<unsigned>(frame.id));
  }
  if (remote) {
    if (fd || frame.length > can::kClassicMaxLength)
      throw HostError(where + ": invalid remote frame");
    if (frame.length > 0) {
      std::snprintf(buffer + used, sizeof buffer - static_cast<std::size_t>(used), "R%u",
                    static_cast<unsigned>(frame.length));
    } else {
      std::snprintf(buffer + used, sizeof buffer - static_cast<std::size_t>(used), "R");
    }
    return buffer;
  }
  if (fd) {
    if (!is_fd_length(frame.length))
      throw HostError(where + ": CAN FD length not expressible as a DLC");
    used += std::snprintf(buffer + used, sizeof buffer - static_cast<std::size_t>(used), "#0");
  } else if (frame.length > can::kClassicMaxLength) {
    throw HostError(where + ": classic frame longer than 8 bytes");
  }
  static const char kHex[] = "0123456789ABCDEF";
  for (std::size_t n = 0; n < frame.length; ++n) {
    buffer[used++] = kHex[frame.data[n] >> 4];
    buffer[used++] = kHex[frame.data[n] & 0x0F];
  }
  buffer[used] = '\0';
  return buffer;
}

}  // namespace

std::vector<LoggedFrame> read_candump_log(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw HostError(path + ": cannot read: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw HostError(path + ": cannot open the candump log");
  std::vector<LoggedFrame> frames;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) {
      throw HostError(path + ":" + std::to_string(line_number) +
                      ": empty line (expected a frame record)");
    }
    frames.push_back(LineParser(path, line_number, line).parse());
  }
  if (in.bad()) throw HostError(path + ": read error");
  return frames;
}

void write_candump_log(const std::string& path, const std::vector<LoggedFrame>& frames) {
  AtomicOutputFile file(path);
  std::string text;
  text.reserve(64);
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const LoggedFrame& logged = frames[n];
    const std::string where = path + ": frame " + std::to_string(n + 1);
    bool printable = true;
    for (const char c : logged.interface) printable = printable && interface_character(c);
    if (logged.interface.empty() || logged.interface.size() > kMaxInterfaceLength || !printable) {
      throw HostError(where +
                      ": interface name must be 1..15 printable ASCII characters other than space");
    }
    char stamp[48];
    std::snprintf(stamp, sizeof stamp, "(%010llu.%06llu) ",
                  static_cast<unsigned long long>(logged.time_us / 1000000u),
                  static_cast<unsigned long long>(logged.time_us % 1000000u));
    text.assign(stamp);
    text += logged.interface;
    text += ' ';
    text += format_frame(logged.frame, where);
    text += '\n';
    file.write(text);
  }
  file.commit();
}

}  // namespace stickslip::host
