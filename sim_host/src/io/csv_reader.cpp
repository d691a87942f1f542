#include "stickslip/host/io/csv_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

// The fuzz target builds the reader with small blocks (fuzz/CMakeLists.txt): block boundaries and
// the growth for long lines are then met by short inputs, and an input costs no 4 MB buffer.
#ifdef STICKSLIP_CSV_BLOCK_BYTES
constexpr std::size_t kBlockBytes = STICKSLIP_CSV_BLOCK_BYTES;
#else
constexpr std::size_t kBlockBytes = std::size_t{1} << 22;
#endif
constexpr double kMaxAbsTime = 0.5 * std::numeric_limits<double>::max();

std::string_view trim(std::string_view text) noexcept {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
    text.remove_suffix(1);
  return text;
}

// A cell as it appears in a message: quoted, shortened if long.
std::string quoted(std::string_view text) {
  constexpr std::size_t kShown = 40;
  if (text.size() > kShown) return "'" + std::string(text.substr(0, kShown)) + "...'";
  return "'" + std::string(text) + "'";
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) {
    if (!out.empty()) out += ",";
    out += name;
  }
  return out;
}

}  // namespace

CsvReader::CsvReader(std::string path) : path_(std::move(path)) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path_, ignored)) {
    throw HostError(path_ + ": cannot read: it is a directory");
  }
  file_ = std::fopen(path_.c_str(), "rb");
  if (file_ == nullptr) throw HostError(path_ + ": cannot open: " + std::strerror(errno));
  // A constructor that throws runs no destructor: close the file here (found by fuzzing: every
  // refused header leaked a FILE, until 'Too many open files').
  try {
    read_header();
  } catch (...) {
    std::fclose(file_);
    file_ = nullptr;
    throw;
  }
}

void CsvReader::read_header() {
  buffer_.resize(kBlockBytes);

  std::string_view header;
  if (!read_line(header)) {
    throw HostError(path_ + ":1: the file is empty; expected a header line naming the columns");
  }
  line_ = 1;
  if (header.size() >= 3 && std::memcmp(header.data(), "\xEF\xBB\xBF", 3) == 0)
    header.remove_prefix(3);  // UTF-8 byte order mark
  if (trim(header).empty()) {
    throw HostError(path_ + ":1: the header line is empty; expected column names such as t,a_u");
  }
  split(header);
  for (std::string_view cell : cells_) {
    std::string_view name = trim(cell);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
      name = name.substr(1, name.size() - 2);
    for (const std::string& seen : columns_) {
      if (seen == name) {
        throw HostError(path_ + ":1: column '" + std::string(name) +
                        "' appears twice in the header");
      }
    }
    columns_.emplace_back(name);
  }
}

CsvReader::~CsvReader() {
  if (file_ != nullptr) std::fclose(file_);
}

std::size_t CsvReader::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == name) return i;
  throw HostError(path_ + ":1: missing column '" + std::string(name) +
                  "' (the header names: " + join(columns_) + ")");
}

bool CsvReader::read_line(std::string_view& line) {
  for (;;) {
    const char* start = buffer_.data() + begin_;
    const void* newline = std::memchr(start, '\n', end_ - begin_);
    if (newline != nullptr) {
      const char* stop = static_cast<const char*>(newline);
      line = std::string_view(start, static_cast<std::size_t>(stop - start));
      begin_ += line.size() + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      return true;
    }
    if (end_of_file_) {
      if (begin_ == end_) return false;
      line = std::string_view(start, end_ - begin_);  // last line without a newline
      begin_ = end_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      return true;
    }
    // Keep the partial line, make room (a line longer than the buffer doubles it) and read on.
    // The cells of the previous row point into the buffer; the caller is done with them.
    std::memmove(buffer_.data(), start, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
    if (end_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);
    const std::size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_);
    end_ += got;
    if (got == 0) {
      if (std::ferror(file_)) throw HostError(path_ + ": read error: " + std::strerror(errno));
      end_of_file_ = true;
    }
  }
}

void CsvReader::split(std::string_view line) {
  cells_.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells_.push_back(line.substr(start));
      return;
    }
    cells_.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

bool CsvReader::next_row() {
  std::string_view text;
  for (;;) {
    if (!read_line(text)) return false;
    ++line_;
    if (!trim(text).empty()) break;  // blank lines (a trailing one, typically) carry no row
  }
  split(text);
  if (cells_.size() != columns_.size()) {
    throw HostError(fmt::format("{}expected {} fields like the header ({}), found {}", where(),
                                columns_.size(), join(columns_), cells_.size()));
  }
  return true;
}

double CsvReader::number(std::size_t column) const {
  const std::string_view text = trim(cells_[column]);
  const auto problem = [&](const std::string& what) {
    return HostError(where() + "column '" + columns_[column] + "': " + what);
  };
  if (text.empty()) throw problem("empty cell, expected a number");
  std::string_view digits = text;
  if (digits.size() > 1 && digits.front() == '+')
    digits.remove_prefix(1);  // from_chars refuses '+'
  double value = 0.0;
  const char* last = digits.data() + digits.size();
  const std::from_chars_result result = std::from_chars(digits.data(), last, value);
  if (result.ec == std::errc::result_out_of_range) {
    throw problem(quoted(text) + " is out of the range of a double");
  }
  if (result.ec != std::errc() || result.ptr != last)
    throw problem(quoted(text) + " is not a number");
  // Classified only: no arithmetic on a NaN or infinity (it would raise FP exceptions).
  if (!std::isfinite(value)) throw problem(quoted(text) + " is not a finite number");
  return value;
}

std::string CsvReader::where() const {
  return path_ + ":" + std::to_string(line_) + ": ";
}

SampledSignal read_signal_csv(const std::string& path) {
  CsvReader reader(path);
  const std::size_t t_column = reader.column("t");
  const std::size_t a_u_column = reader.column("a_u");
  const auto& names = reader.columns();
  const bool actuated = std::find(names.begin(), names.end(), "f_a") != names.end();
  const std::size_t f_a_column = actuated ? reader.column("f_a") : 0;
  SampledSignal signal;
  double first_step = 0.0;
  while (reader.next_row()) {
    const double t = reader.number(t_column);
    // Keeps every difference of two times finite (t = 1e308 after -1e308 would overflow, raise
    // FE_OVERFLOW and give dt = inf).
    if (!(std::fabs(t) <= kMaxAbsTime)) {
      throw HostError(fmt::format("{}column 't': {} is beyond the time range |t| <= {} s",
                                  reader.where(), t, kMaxAbsTime));
    }
    const double a_u = reader.number(a_u_column);
    const std::size_t n = signal.t_s.size();
    if (n >= 1) {
      const double previous = signal.t_s.back();
      const double step = t - previous;
      if (!(step > 0.0)) {
        throw HostError(fmt::format("{}column 't': t must increase, got {} after {}",
                                    reader.where(), t, previous));
      }
      if (n == 1) {
        first_step = step;
      } else if (std::fabs(step - first_step) > kUniformStepTolerance * first_step) {
        throw HostError(
            fmt::format("{}column 't': t is not uniform: the step {} s differs from the first step "
                        "{} s by more "
                        "than {} of it",
                        reader.where(), step, first_step, kUniformStepTolerance));
      }
    }
    signal.t_s.push_back(t);
    signal.a_u_m_per_s2.push_back(a_u);
    if (actuated) signal.f_a_n.push_back(reader.number(f_a_column));
  }
  const std::size_t n = signal.t_s.size();
  if (n < 2) {
    throw HostError(fmt::format("{}{} sample{} after the header; at least 2 are needed",
                                reader.where(), n == 0 ? "no" : "only 1", n == 0 ? "s" : ""));
  }
  signal.dt_s = (signal.t_s.back() - signal.t_s.front()) / static_cast<double>(n - 1);
  return signal;
}

}  // namespace stickslip::host
