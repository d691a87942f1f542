// Format detection and the candump reader for recordings. The candump grammar is that of
// candump_log.cpp (can-utils' parse_canframe made strict), with what recordings from other
// machines add: CRLF line ends, blank lines, and remote, error and FD frames counted rather than
// returned (a signal is decoded from data frames only).
#include "stickslip/host/io/can_log.hpp"

#include <cctype>
#include <charconv>
#include <set>

#include "stickslip/host/error.hpp"
#include "text_lines.hpp"

namespace stickslip::host {
namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool starts_with_ignoring_case(std::string_view text, std::string_view prefix) {
  if (text.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != prefix[i]) return false;
  return true;
}

bool candump_record(std::string_view line) {
  // "(digits.digits) "
  if (line.empty() || line[0] != '(') return false;
  std::size_t at = 1;
  const std::size_t digits = at;
  while (at < line.size() && std::isdigit(static_cast<unsigned char>(line[at]))) ++at;
  if (at == digits || at >= line.size() || line[at] != '.') return false;
  ++at;
  const std::size_t fraction = at;
  while (at < line.size() && std::isdigit(static_cast<unsigned char>(line[at]))) ++at;
  return at > fraction && at + 1 < line.size() && line[at] == ')' && line[at + 1] == ' ' &&
         line.find('#', at) != std::string_view::npos;
}

std::string_view extension(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  const std::size_t slash = path.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  return std::string_view(path).substr(dot + 1);
}

class CandumpLine {
 public:
  CandumpLine(const std::string& path, std::size_t line, std::string_view text)
      : path_(path), line_(line), text_(text) {}

  // False for a record that is valid but not a classic data frame.
  bool parse(LogFrame& frame) {
    expect('(', "expected '(' opening the timestamp");
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != ')') ++at_;
    const std::string_view stamp = text_.substr(start, at_ - start);
    expect(')', "expected ')' closing the timestamp");
    const auto result = std::from_chars(stamp.data(), stamp.data() + stamp.size(), frame.time_s);
    if (stamp.empty() || result.ec != std::errc() || result.ptr != stamp.data() + stamp.size() ||
        stamp.find_first_not_of("0123456789.") != std::string_view::npos) {
      fail("timestamp " + text::quoted(stamp) + " is not seconds.fraction");
    }
    expect(' ', "expected one space after the timestamp");
    const std::size_t name = at_;
    while (at_ < text_.size() && text_[at_] > ' ' && text_[at_] < 0x7F) ++at_;
    if (at_ == name || at_ - name > 15) fail("expected an interface name of 1..15 characters");
    frame.channel = std::string(text_.substr(name, at_ - name));
    expect(' ', "expected one space after the interface name");
    const std::size_t hash = text_.find('#', at_);
    if (hash == std::string_view::npos) fail("expected ID#data (no '#')");
    const std::size_t id_digits = hash - at_;
    if (id_digits != 3 && id_digits != 8)
      fail("the CAN id must have 3 or 8 hex digits, not " + std::to_string(id_digits));
    std::uint32_t id = 0;
    for (std::size_t n = 0; n < id_digits; ++n) {
      const int digit = hex_value(text_[at_ + n]);
      if (digit < 0) fail("CAN id " + text::quoted(text_.substr(at_, id_digits)) + " is not hex");
      id = (id << 4) | static_cast<std::uint32_t>(digit);
    }
    at_ = hash + 1;
    bool data_frame = true;
    if (id_digits == 3) {
      if (id > 0x7FFu) fail("standard id above 7FF");
    } else if ((id & 0x20000000u) != 0) {
      data_frame = false;  // error frame
    } else {
      if (id > 0x1FFFFFFFu) fail("extended id above 1FFFFFFF");
      frame.extended = true;
    }
    frame.id = id;
    if (at_ < text_.size() && (text_[at_] == 'R' || text_[at_] == 'r' || text_[at_] == '#')) {
      data_frame = false;  // remote request or CAN FD
      while (at_ < text_.size() && text_[at_] != ' ') ++at_;
    }
    std::size_t length = 0;
    while (data_frame && at_ < text_.size() && text_[at_] != ' ') {
      if (text_[at_] == '.' && length > 0) ++at_;
      if (at_ + 1 >= text_.size()) fail("odd number of hex digits in the data");
      const int high = hex_value(text_[at_]);
      const int low = hex_value(text_[at_ + 1]);
      if (high < 0 || low < 0) fail("data must be hex byte pairs");
      if (length == 8) fail("more than 8 data bytes in a classic frame");
      frame.data[length++] = static_cast<std::uint8_t>((high << 4) | low);
      at_ += 2;
    }
    frame.length = frame.dlc = static_cast<std::uint8_t>(length);
    if (at_ < text_.size()) {
      const std::string_view rest = text_.substr(at_);
      if (rest == " R" || rest == " T") {
        frame.direction = rest[1];
      } else if (data_frame) {
        fail("unexpected " + text::quoted(rest) + " after the frame");
      }
    }
    return data_frame;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { text::fail(path_, line_, what); }
  void expect(char c, const char* what) {
    if (at_ >= text_.size() || text_[at_] != c) fail(what);
    ++at_;
  }

  const std::string& path_;
  std::size_t line_;
  std::string_view text_;
  std::size_t at_ = 0;
};

}  // namespace

const char* format_name(CanLogFormat format) noexcept {
  switch (format) {
    case CanLogFormat::kCandump:
      return "candump";
    case CanLogFormat::kAsc:
      return "Vector ASC";
    case CanLogFormat::kBlf:
      return "Vector BLF";
    case CanLogFormat::kTrc:
      return "PEAK TRC";
  }
  return "?";
}

CanLogFormat detect_can_log_format(std::string_view head, const std::string& path) {
  if (head.size() >= 4 && head.substr(0, 4) == "LOGG") return CanLogFormat::kBlf;
  const std::vector<std::string_view> lines = text::split_lines(head);
  constexpr std::size_t kLinesLooked = 64;
  for (std::size_t n = 0; n < lines.size() && n < kLinesLooked; ++n) {
    const std::string_view line = text::trim(lines[n]);
    if (line.empty()) continue;
    if (line.substr(0, 13) == ";$FILEVERSION") return CanLogFormat::kTrc;
    if (starts_with_ignoring_case(line, "date ") || starts_with_ignoring_case(line, "base hex") ||
        starts_with_ignoring_case(line, "base dec") ||
        starts_with_ignoring_case(line, "begin triggerblock"))
      return CanLogFormat::kAsc;
    if (candump_record(line)) return CanLogFormat::kCandump;
  }
  const std::string_view ext = extension(path);
  if (ext == "blf" || ext == "BLF") return CanLogFormat::kBlf;
  if (ext == "asc" || ext == "ASC") return CanLogFormat::kAsc;
  if (ext == "trc" || ext == "TRC") return CanLogFormat::kTrc;
  if (ext == "log") return CanLogFormat::kCandump;
  throw HostError(path +
                  ": not a CAN log this tool reads (no BLF 'LOGG' signature, ASC 'date'/'base' "
                  "line, TRC ';$FILEVERSION' line or candump '(seconds) interface id#data' "
                  "record, and no .blf, .asc, .trc or .log extension)");
}

std::vector<std::string> log_channels(const CanLog& log) {
  std::set<std::string> channels;
  for (const LogFrame& frame : log.frames) channels.insert(frame.channel);
  return {channels.begin(), channels.end()};
}

CanLogFormat detect_can_log_format(const std::string& path) {
  const std::string bytes = text::read_file(path);
  return detect_can_log_format(std::string_view(bytes).substr(0, 8192), path);
}

CanLog read_can_log(const std::string& path) {
  const std::string bytes = text::read_file(path);
  switch (detect_can_log_format(std::string_view(bytes).substr(0, 8192), path)) {
    case CanLogFormat::kBlf:
      return parse_blf(bytes, path);
    case CanLogFormat::kAsc:
      return parse_asc(bytes, path);
    case CanLogFormat::kTrc:
      return parse_trc(bytes, path);
    case CanLogFormat::kCandump:
      break;
  }
  return parse_candump_text(bytes, path);
}

CanLog parse_candump_text(std::string_view bytes, const std::string& path) {
  CanLog log;
  log.format = CanLogFormat::kCandump;
  const std::vector<std::string_view> lines = text::split_lines(bytes);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    if (text::trim(lines[n]).empty()) continue;
    LogFrame frame;
    if (CandumpLine(path, n + 1, lines[n]).parse(frame)) {
      frame.line = n + 1;
      log.frames.push_back(std::move(frame));
    } else {
      ++log.skipped_events;
    }
  }
  return log;
}

}  // namespace stickslip::host
