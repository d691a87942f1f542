// PEAK TRC (PCAN-View, PCAN-Explorer), after PEAK's "PCAN-Trace file format" description.
//
//   ;$FILEVERSION=2.1
//   ;$STARTTIME=46351.5004
//   ;$COLUMNS=N,O,T,B,I,d,R,L,D
//         1        1.000 DT  1     0123 Rx -  8    00 11 22 33 44 55 66 77
//
// Version 2.x lines have the columns ;$COLUMNS names (2.0 without it: N,O,T,I,d,l,D):
// N number, O time offset in ms, T type (DT data frame; RR remote, FD/FB/FE/BI CAN FD, ER, ST,
// EC, EV events: counted and skipped), B bus, I id (hex; 8 digits or more than 4 -> extended),
// d direction, R reserved, L DLC, l data length, D data bytes. Version 1.x lines are
// "N) O [B] T I [-] L D" (1.0 has no type; 1.2 adds the bus, 1.3 the reserved '-'); a type other
// than Rx/Tx, or "RTR" in place of the data, is an event counted and skipped. No ;$FILEVERSION
// means 1.0. Times are the offsets / 1000 (s since ;$STARTTIME, which is not applied).
#include <charconv>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"
#include "text_lines.hpp"

namespace stickslip::host {
namespace {

bool hex(std::string_view field, std::uint32_t& value) {
  if (field.empty()) return false;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value, 16);
  return result.ec == std::errc() && result.ptr == field.data() + field.size();
}

bool decimal(std::string_view field, std::uint32_t& value) {
  if (field.empty()) return false;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
  return result.ec == std::errc() && result.ptr == field.data() + field.size();
}

constexpr std::uint8_t kFdLengths[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};

}  // namespace

CanLog parse_trc(std::string_view bytes, const std::string& path) {
  CanLog log;
  log.format = CanLogFormat::kTrc;
  int major = 1, minor = 0;
  std::string columns;
  const std::vector<std::string_view> lines = text::split_lines(bytes);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::string_view line = text::trim(lines[n]);
    const auto fail = [&](const std::string& what) { text::fail(path, n + 1, what); };
    if (line.empty()) continue;
    if (line.front() == ';') {
      if (line.substr(0, 14) == ";$FILEVERSION=") {
        const std::string_view version = text::trim(line.substr(14));
        if (version == "1.0")
          major = 1, minor = 0;
        else if (version == "1.1")
          major = 1, minor = 1;
        else if (version == "1.2")
          major = 1, minor = 2;
        else if (version == "1.3")
          major = 1, minor = 3;
        else if (version == "2.0")
          major = 2, minor = 0;
        else if (version == "2.1")
          major = 2, minor = 1;
        else
          fail("TRC file version " + text::quoted(version) + " is not 1.0..1.3, 2.0 or 2.1");
      } else if (line.substr(0, 10) == ";$COLUMNS=") {
        columns.clear();
        for (const char c : line.substr(10))
          if (c != ',' && !text::is_space(c)) columns += c;
        if (columns.find('N') == std::string::npos || columns.find('O') == std::string::npos ||
            columns.find('I') == std::string::npos || columns.find('D') == std::string::npos ||
            columns.back() != 'D')
          fail(";$COLUMNS must name N, O, I and end with D, found " +
               text::quoted(line.substr(10)));
      }
      continue;
    }
    const std::vector<std::string_view> fields = text::split_blanks(line);
    std::string layout;
    if (major == 2) {
      layout = columns.empty() ? "NOTIdlD" : columns;
    } else {
      layout = minor == 0 ? "NOILD" : minor == 1 ? "NOTILD" : minor == 2 ? "NOBTILD" : "NOBTIRLD";
    }
    LogFrame frame;
    std::size_t field = 0;
    bool data_frame = true;
    std::uint32_t value = 0;
    bool have_length = false;
    for (const char column : layout) {
      if (column == 'D') break;
      if (field >= fields.size())
        fail("expected the columns " + layout + ", the line ends after " + std::to_string(field));
      const std::string_view f = fields[field++];
      switch (column) {
        case 'N':
          break;
        case 'O': {
          double offset_ms = 0.0;
          const auto result = std::from_chars(f.data(), f.data() + f.size(), offset_ms);
          if (result.ec != std::errc() || result.ptr != f.data() + f.size() ||
              !(offset_ms >= -1e15 && offset_ms <= 1e15))
            fail("time offset " + text::quoted(f) + " is not milliseconds");
          frame.time_s = offset_ms / 1000.0;
          break;
        }
        case 'T':
          if (major == 2) {
            data_frame = data_frame && f == "DT";
          } else if (f == "Rx" || f == "Tx") {
            frame.direction = f[0];
          } else {
            data_frame = false;
          }
          break;
        case 'B':
          frame.channel = std::string(f);
          break;
        case 'I':
          if (!hex(f, frame.id) && data_frame) fail("CAN id " + text::quoted(f) + " is not hex");
          frame.extended = f.size() > 4;
          if (data_frame && frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu))
            fail("CAN id " + text::quoted(f) + " is beyond its width");
          break;
        case 'd':
          if (f == "Rx" || f == "Tx") frame.direction = f[0];
          break;
        case 'L':
          if (!decimal(f, value) || value > 15) {
            if (data_frame) fail("DLC " + text::quoted(f) + " is not 0..15");
          } else if (!have_length) {
            frame.dlc = static_cast<std::uint8_t>(value);
            frame.length = static_cast<std::uint8_t>(value < 8 ? value : 8);
          }
          break;
        case 'l':
          if (!decimal(f, value) || value > 64) {
            if (data_frame) fail("data length " + text::quoted(f) + " is not 0..64");
          } else {
            have_length = true;
            frame.length = static_cast<std::uint8_t>(value < 8 ? value : 8);
            frame.dlc = static_cast<std::uint8_t>(value);
            for (std::uint8_t code = 0; code < 16; ++code)
              if (kFdLengths[code] == value) frame.dlc = code;
            if (value > 8) data_frame = false;  // only a CAN FD frame is longer
          }
          break;
        default:
          break;  // R and columns this reader does not use
      }
    }
    if (data_frame && field < fields.size() && fields[field] == "RTR") data_frame = false;
    if (!data_frame) {
      ++log.skipped_events;
      continue;
    }
    if (fields.size() < field + frame.length) {
      fail("DLC " + std::to_string(frame.dlc) + " but " + std::to_string(fields.size() - field) +
           " data bytes");
    }
    for (std::size_t i = 0; i < frame.length; ++i) {
      if (!hex(fields[field + i], value) || value > 0xFF || fields[field + i].size() > 2)
        fail("data byte " + std::to_string(i + 1) + " " + text::quoted(fields[field + i]) +
             " is not a hex byte");
      frame.data[i] = static_cast<std::uint8_t>(value);
    }
    log.frames.push_back(std::move(frame));
  }
  return log;
}

}  // namespace stickslip::host
