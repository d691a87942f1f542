// Helpers for the tests of the host library and the command line: a fresh temporary directory
// per test and small file utilities. Header-only so every test file stands alone.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

namespace stickslip::test {

// A directory of its own under the system temp directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "stickslip-test-XXXXXX").string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (::mkdtemp(buffer.data()) != nullptr) path_ = buffer.data();
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  bool ok() const { return !path_.empty(); }
  std::string file(const std::string& name) const {
    return (std::filesystem::path(path_) / name).string();
  }
  // Names of everything in the directory (hidden temporaries included), sorted.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  std::string path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline bool exists(const std::string& path) {
  return std::filesystem::exists(path);
}

inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string::size_type start = 0;
  while (start < text.size()) {
    const auto end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

inline std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string::size_type start = 0;
  for (;;) {
    const auto comma = line.find(',', start);
    cells.push_back(
        line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

// A numeric CSV: the header and every row parsed back with from_chars (exact for %.17g text).
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  bool ok = true;  // every cell was a number
};

inline Table read_table(const std::string& path) {
  Table table;
  const std::vector<std::string> lines = split_lines(read_text(path));
  if (lines.empty()) {
    table.ok = false;
    return table;
  }
  table.header = split_cells(lines[0]);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::vector<double> row;
    for (const std::string& cell : split_cells(lines[i])) {
      double value = 0.0;
      const auto result = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (result.ec != std::errc() || result.ptr != cell.data() + cell.size()) table.ok = false;
      row.push_back(value);
    }
    table.rows.push_back(row);
  }
  return table;
}

inline std::vector<double> column(const Table& table, std::size_t index) {
  std::vector<double> values;
  for (const auto& row : table.rows) values.push_back(row.at(index));
  return values;
}

// 64-bit FNV-1a of a byte string: a compact fingerprint of a generated file.
inline std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

inline bool bit_equal(double a, double b) {
  std::uint64_t x, y;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x == y;
}

}  // namespace stickslip::test
