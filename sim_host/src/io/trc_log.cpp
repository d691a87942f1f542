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

// Where a problem is: the file and the 1-based line.
struct TrcPlace {
  const std::string& path;
  std::size_t line;
  [[noreturn]] void fail(const std::string& what) const { text::fail(path, line, what); }
};

struct TrcVersion {
  int major = 1, minor = 0;
  std::string columns;  // 2.x: the ;$COLUMNS letters without separators

  // The letters of a frame line's columns, up to the data bytes (D).
  std::string layout() const {
    if (major == 2) return columns.empty() ? "NOTIdlD" : columns;
    return minor == 0 ? "NOILD" : minor == 1 ? "NOTILD" : minor == 2 ? "NOBTILD" : "NOBTIRLD";
  }
};

// A ";" line: the file version and the 2.x column list; other comments are skipped.
void read_trc_header(std::string_view line, TrcVersion& version, const TrcPlace& place) {
  if (line.substr(0, 14) == ";$FILEVERSION=") {
    const std::string_view text = text::trim(line.substr(14));
    static constexpr const char* kVersions[] = {"1.0", "1.1", "1.2", "1.3", "2.0", "2.1"};
    for (const char* known : kVersions) {
      if (text == known) {
        version.major = known[0] - '0';
        version.minor = known[2] - '0';
        return;
      }
    }
    place.fail("TRC file version " + text::quoted(text) + " is not 1.0..1.3, 2.0 or 2.1");
  }
  if (line.substr(0, 10) == ";$COLUMNS=") {
    std::string& columns = version.columns;
    columns.clear();
    for (const char c : line.substr(10))
      if (c != ',' && !text::is_space(c)) columns += c;
    if (columns.find('N') == std::string::npos || columns.find('O') == std::string::npos ||
        columns.find('I') == std::string::npos || columns.find('D') == std::string::npos ||
        columns.back() != 'D')
      place.fail(";$COLUMNS must name N, O, I and end with D, found " +
                 text::quoted(line.substr(10)));
  }
}

// One frame line's fields before the data bytes.
struct TrcFields {
  LogFrame frame;
  std::size_t data_field = 0;  // index of the first data byte
  bool data_frame = true;      // false: remote, error, CAN FD or another event
  bool have_length = false;
};

void read_trc_length(char column, std::string_view f, TrcFields& out, const TrcPlace& place) {
  std::uint32_t value = 0;
  LogFrame& frame = out.frame;
  if (column == 'L') {
    if (!decimal(f, value) || value > 15) {
      if (out.data_frame) place.fail("DLC " + text::quoted(f) + " is not 0..15");
    } else if (!out.have_length) {
      frame.dlc = static_cast<std::uint8_t>(value);
      frame.length = static_cast<std::uint8_t>(value < 8 ? value : 8);
    }
    return;
  }
  if (!decimal(f, value) || value > 64) {
    if (out.data_frame) place.fail("data length " + text::quoted(f) + " is not 0..64");
    return;
  }
  out.have_length = true;
  frame.length = static_cast<std::uint8_t>(value < 8 ? value : 8);
  frame.dlc = static_cast<std::uint8_t>(value);
  for (std::uint8_t code = 0; code < 16; ++code)
    if (kFdLengths[code] == value) frame.dlc = code;
  if (value > 8) out.data_frame = false;  // only a CAN FD frame is longer
}

void read_trc_column(char column, std::string_view f, int major, TrcFields& out,
                     const TrcPlace& place) {
  LogFrame& frame = out.frame;
  switch (column) {
    case 'O': {
      double offset_ms = 0.0;
      const auto result = std::from_chars(f.data(), f.data() + f.size(), offset_ms);
      if (result.ec != std::errc() || result.ptr != f.data() + f.size() ||
          !(offset_ms >= -1e15 && offset_ms <= 1e15))
        place.fail("time offset " + text::quoted(f) + " is not milliseconds");
      frame.time_s = offset_ms / 1000.0;
      break;
    }
    case 'T':
      if (major == 2) {
        out.data_frame = out.data_frame && f == "DT";
      } else if (f == "Rx" || f == "Tx") {
        frame.direction = f[0];
      } else {
        out.data_frame = false;
      }
      break;
    case 'B':
      frame.channel = std::string(f);
      break;
    case 'I':
      if (!hex(f, frame.id) && out.data_frame)
        place.fail("CAN id " + text::quoted(f) + " is not hex");
      frame.extended = f.size() > 4;
      if (out.data_frame && frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu))
        place.fail("CAN id " + text::quoted(f) + " is beyond its width");
      break;
    case 'd':
      if (f == "Rx" || f == "Tx") frame.direction = f[0];
      break;
    case 'L':
    case 'l':
      read_trc_length(column, f, out, place);
      break;
    default:
      break;  // N, R and columns this reader does not use
  }
}

// A frame line: false for an event that is not a classic data frame (counted by the caller).
bool read_trc_frame(const std::vector<std::string_view>& fields, const TrcVersion& version,
                    LogFrame& frame, const TrcPlace& place) {
  const std::string layout = version.layout();
  TrcFields out;
  std::size_t field = 0;
  for (const char column : layout) {
    if (column == 'D') break;
    if (field >= fields.size())
      place.fail("expected the columns " + layout + ", the line ends after " +
                 std::to_string(field));
    read_trc_column(column, fields[field++], version.major, out, place);
  }
  if (out.data_frame && field < fields.size() && fields[field] == "RTR") out.data_frame = false;
  if (!out.data_frame) return false;
  frame = std::move(out.frame);
  if (fields.size() < field + frame.length) {
    place.fail("DLC " + std::to_string(frame.dlc) + " but " +
               std::to_string(fields.size() - field) + " data bytes");
  }
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < frame.length; ++i) {
    if (!hex(fields[field + i], value) || value > 0xFF || fields[field + i].size() > 2)
      place.fail("data byte " + std::to_string(i + 1) + " " + text::quoted(fields[field + i]) +
                 " is not a hex byte");
    frame.data[i] = static_cast<std::uint8_t>(value);
  }
  return true;
}

}  // namespace

CanLog parse_trc(std::string_view bytes, const std::string& path) {
  CanLog log;
  log.format = CanLogFormat::kTrc;
  TrcVersion version;
  const std::vector<std::string_view> lines = text::split_lines(bytes);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::string_view line = text::trim(lines[n]);
    const TrcPlace place{path, n + 1};
    if (line.empty()) continue;
    if (line.front() == ';') {
      read_trc_header(line, version, place);
      continue;
    }
    LogFrame frame;
    if (read_trc_frame(text::split_blanks(line), version, frame, place)) {
      frame.line = n + 1;
      log.frames.push_back(std::move(frame));
    } else {
      ++log.skipped_events;
    }
  }
  return log;
}

}  // namespace stickslip::host
