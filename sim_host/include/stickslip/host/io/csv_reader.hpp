// Streaming CSV reader for numeric tables: a header line naming the columns, then one row per
// line. Reads the file in large blocks and parses numbers with std::from_chars (1e7 rows load in
// about a second). Every problem is a HostError naming the file, the 1-based line and the column.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace stickslip::host {

class CsvReader {
 public:
  // Opens `path` and reads the header line.
  explicit CsvReader(std::string path);
  ~CsvReader();
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  const std::string& path() const noexcept { return path_; }
  const std::vector<std::string>& columns() const noexcept { return columns_; }
  // Index of the column called `name`; throws "IN.csv:1: missing column 'a_u' (...)" if absent.
  std::size_t column(std::string_view name) const;

  // Advances to the next data row, skipping blank lines; false at the end of the file.
  bool next_row();
  // 1-based line number of the current row (of the last line read once next_row() is false).
  std::size_t line() const noexcept { return line_; }
  // The cell of `column` in the current row as a finite number.
  double number(std::size_t column) const;
  // "IN.csv:17: " - the start of a message about the current row.
  std::string where() const;

 private:
  void read_header();
  bool read_line(std::string_view& line);
  void split(std::string_view line);

  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;  // unread data is buffer_[begin_, end_)
  std::size_t end_ = 0;
  bool end_of_file_ = false;
  std::size_t line_ = 0;
  std::vector<std::string> columns_;
  std::vector<std::string_view> cells_;  // into buffer_, valid until the next read
};

// A uniformly sampled signal: the columns t (s) and a_u (m/s^2) of a CSV file.
struct SampledSignal {
  std::vector<double> t_s;
  std::vector<double> a_u_m_per_s2;
  double dt_s = 0.0;  // (t_last - t_0) / (n - 1)
  // The optional column f_a: an actuator force (N, on the seat, upward positive), f_a[n] held over
  // the step from t[n-1] to t[n]. Empty when the file has no such column.
  std::vector<double> f_a_n;
};

// Relative tolerance on every step t[i] - t[i-1] against the first step.
inline constexpr double kUniformStepTolerance = 1e-6;

// Reads columns `t`, `a_u` and, if present, `f_a` (others are ignored); requires at least 2
// samples, finite values and a uniform, increasing t.
SampledSignal read_signal_csv(const std::string& path);

}  // namespace stickslip::host
