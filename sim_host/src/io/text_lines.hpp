// What the text recording readers share: a whole file in memory split into lines (LF or CRLF,
// a UTF-8 byte order mark removed), and "FILE:LINE: problem" messages. Private to src/io/.
#pragma once

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "stickslip/host/error.hpp"

namespace stickslip::host::text {

// Whole-file reads: recordings are tens of megabytes at most, and a reader that sees every line
// at once can detect the layout (separator, header) before it parses a number.
inline std::string read_file(const std::string& path) {
  // A directory opens as a stream, and its first read throws a message that names no file.
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw HostError(path + ": cannot read: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw HostError(path + ": cannot open: " + std::strerror(errno));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw HostError(path + ": read error");
  return bytes;
}

// Lines of `bytes` without their terminators; views into `bytes`.
inline std::vector<std::string_view> split_lines(std::string_view bytes) {
  if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start < bytes.size()) {
    std::size_t end = bytes.find('\n', start);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

inline std::string_view trim(std::string_view text) {
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

// Fields separated by runs of blanks.
inline std::vector<std::string_view> split_blanks(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && is_space(line[at])) ++at;
    const std::size_t start = at;
    while (at < line.size() && !is_space(line[at])) ++at;
    if (at > start) fields.push_back(line.substr(start, at - start));
  }
  return fields;
}

// A piece of input in a message: quoted, control bytes shown as '?', shortened if long.
inline std::string quoted(std::string_view text) {
  constexpr std::size_t kShown = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < kShown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c < 0x20 || c == 0x7F) ? '?' : static_cast<char>(c);
  }
  if (text.size() > kShown) out += "...";
  return out + "'";
}

[[noreturn]] inline void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw HostError(path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace stickslip::host::text
