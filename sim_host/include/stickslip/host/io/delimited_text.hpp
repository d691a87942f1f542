// Delimited text recordings as loggers write them: a table of numbers separated by ',', ';', a tab
// or blanks, with '.' or ',' as the decimal mark (',' only with ';' or tab separators), after
// any number of banner or comment lines, under an optional header naming the columns and their
// units ("Time [s]", "AccZ [g]", "a_u (m/s^2)"). The layout is detected from the file itself;
// docs/RECORDINGS.md states the rules. Numbers are parsed with std::from_chars, so a value reads
// to the same double as in CsvReader.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace stickslip::host {

struct TextChannel {
  std::string name;  // the header's name without its unit; "column N" when there is no header
  std::string unit;  // as written in the header ("m/s^2", "g", "mm/s²"); empty when none
  std::vector<double> values;
};

struct DelimitedTable {
  std::string path;
  char separator = ',';  // ',', ';', '\t', or ' ' for runs of blanks
  char decimal_mark = '.';
  std::size_t header_line = 0;         // 1-based; 0 when the file has no header
  std::size_t first_data_line = 0;     // 1-based
  std::vector<std::size_t> row_lines;  // the 1-based line of each row (blank lines are skipped)
  std::vector<TextChannel> channels;

  // By name (exact, then ignoring ASCII case) or by 1-based index ("2"); throws a HostError
  // listing the columns when nothing matches.
  const TextChannel& channel(std::string_view selector) const;
};

// Reads every column; throws HostError "FILE:LINE: problem" for a row that is not numbers of the
// detected layout, and "FILE: problem" when the file holds no numeric table.
DelimitedTable read_delimited_text(const std::string& path);

// The table of `bytes` as if read from `path` (for tests and the fuzzer).
DelimitedTable parse_delimited_text(std::string_view bytes, const std::string& path);

// "Time [s]" -> {"Time", "s"}; "a_u (m/s^2)" -> {"a_u", "m/s^2"}; "t" -> {"t", ""}.
struct NameAndUnit {
  std::string name;
  std::string unit;
};
NameAndUnit split_name_and_unit(std::string_view header_cell);

}  // namespace stickslip::host
