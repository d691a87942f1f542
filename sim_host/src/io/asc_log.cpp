// Vector ASC: a text log of CANalyzer/CANoe and many loggers.
//
//   date Wed Nov 25 01:02:03.000 pm 2026
//   base hex  timestamps absolute
//   internal events logged
//   Begin Triggerblock Wed Nov 25 01:02:03.000 pm 2026
//      0.000000 Start of measurement
//      0.001000 1  123             Rx   d 8 00 11 22 33 44 55 66 77
//      0.002000 1  18FEF100x       Rx   d 8 ...        (extended id: 'x' suffix)
//   End TriggerBlock
//
// A classic data frame is "time channel id Rx|Tx d dlc bytes...", anything after the bytes
// (Length = ..., BitCount = ...) being read over. Every other line (remote frames 'r',
// ErrorFrame, CANFD, statistics, J1939, comments) is an event counted and skipped. "base dec"
// makes ids and bytes decimal; "timestamps relative" makes every time a delta to the previous
// event, summed here (python-can reads both kinds as absolute).
#include <cctype>
#include <charconv>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"
#include "text_lines.hpp"

namespace stickslip::host {
namespace {

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

bool decimal_time(std::string_view field, double& value) {
  if (field.empty() || !std::isdigit(static_cast<unsigned char>(field[0]))) return false;
  if (field.find_first_not_of("0123456789.") != std::string_view::npos) return false;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
  return result.ec == std::errc() && result.ptr == field.data() + field.size();
}

bool integer(std::string_view field, int base, std::uint32_t& value) {
  if (field.empty()) return false;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value, base);
  return result.ec == std::errc() && result.ptr == field.data() + field.size();
}

bool is_direction(std::string_view field) {
  return equal_ignoring_case(field, "Rx") || equal_ignoring_case(field, "Tx");
}

bool is_data(std::string_view field) {
  return field == "d" || field == "D";
}

// Hex digits, optionally with the extended id's 'x': a CAN id in either base.
bool looks_like_id(std::string_view field) {
  if (!field.empty() && (field.back() == 'x' || field.back() == 'X')) field.remove_suffix(1);
  return !field.empty() &&
         field.find_first_not_of("0123456789abcdefABCDEF") == std::string_view::npos;
}

}  // namespace

CanLog parse_asc(std::string_view bytes, const std::string& path) {
  CanLog log;
  log.format = CanLogFormat::kAsc;
  int base = 16;
  bool relative = false;
  double previous_time = 0.0;
  const std::vector<std::string_view> lines = text::split_lines(bytes);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::vector<std::string_view> fields = text::split_blanks(lines[n]);
    if (fields.empty()) continue;
    const auto fail = [&](const std::string& what) { text::fail(path, n + 1, what); };
    if (equal_ignoring_case(fields[0], "base")) {
      if (fields.size() < 2 ||
          !(equal_ignoring_case(fields[1], "hex") || equal_ignoring_case(fields[1], "dec")))
        fail("expected 'base hex' or 'base dec'");
      base = equal_ignoring_case(fields[1], "hex") ? 16 : 10;
      if (fields.size() >= 4 && equal_ignoring_case(fields[2], "timestamps"))
        relative = equal_ignoring_case(fields[3], "relative");
      continue;
    }
    // A data frame is known by its shape (direction then 'd'), so that one with a damaged time,
    // channel or direction is refused rather than taken for an event and read over as a gap.
    const bool data_frame = fields.size() >= 5 && is_direction(fields[3]) && is_data(fields[4]);
    double time_s = 0.0;
    if (!data_frame && fields.size() >= 5 && is_data(fields[3]) && looks_like_id(fields[2]) &&
        decimal_time(fields[0], time_s)) {
      fail("data frame without its direction (Rx or Tx) before " + text::quoted(fields[3]));
    }
    if (!decimal_time(fields[0], time_s)) {
      if (data_frame) fail("time " + text::quoted(fields[0]) + " is not seconds (a decimal >= 0)");
      continue;  // header, trigger block or comment line
    }
    if (relative) {
      time_s += previous_time;
      previous_time = time_s;
    }
    // time channel id dir d dlc data...
    std::uint32_t channel = 0;
    if (!data_frame) {
      ++log.skipped_events;
      continue;
    }
    if (!integer(fields[1], 10, channel))
      fail("channel " + text::quoted(fields[1]) + " is not a number");
    if (fields.size() < 6) fail("data frame without its DLC");
    LogFrame frame;
    frame.time_s = time_s;
    frame.channel = std::string(fields[1]);
    frame.direction = fields[3][0] == 'R' || fields[3][0] == 'r' ? 'R' : 'T';
    std::string_view id = fields[2];
    if (!id.empty() && (id.back() == 'x' || id.back() == 'X')) {
      frame.extended = true;
      id.remove_suffix(1);
    }
    if (!integer(id, base, frame.id) || frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu)) {
      fail("CAN id " + text::quoted(fields[2]) + " is not a " + (frame.extended ? "29" : "11") +
           "-bit " + (base == 16 ? "hex" : "decimal") + " id");
    }
    std::uint32_t dlc = 0;
    if (!integer(fields[5], base, dlc) || dlc > 15)
      fail("DLC " + text::quoted(fields[5]) + " is not 0..15");
    frame.dlc = static_cast<std::uint8_t>(dlc);
    frame.length = static_cast<std::uint8_t>(dlc < 8 ? dlc : 8);
    if (fields.size() < 6u + frame.length) {
      fail("DLC " + std::to_string(dlc) + " but " + std::to_string(fields.size() - 6) +
           " data bytes");
    }
    for (std::size_t i = 0; i < frame.length; ++i) {
      std::uint32_t byte = 0;
      if (!integer(fields[6 + i], base, byte) || byte > 0xFF)
        fail("data byte " + std::to_string(i + 1) + " " + text::quoted(fields[6 + i]) +
             " is not a byte");
      frame.data[i] = static_cast<std::uint8_t>(byte);
    }
    frame.line = n + 1;
    log.frames.push_back(std::move(frame));
  }
  return log;
}

}  // namespace stickslip::host
