#include "stickslip/host/io/delimited_text.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <system_error>

#include "stickslip/host/error.hpp"
#include "text_lines.hpp"

namespace stickslip::host {
namespace {

struct Layout {
  char separator;
  char decimal_mark;
};

// Tried in this order; on a tie (same number of columns) the earlier one wins, so a tab-separated
// file is not read as blank-separated.
constexpr Layout kLayouts[] = {{',', '.'},  {';', '.'},  {';', ','},
                               {'\t', '.'}, {'\t', ','}, {' ', '.'}};

std::vector<std::string_view> split(std::string_view line, char separator) {
  if (separator == ' ') return text::split_blanks(line);
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t at = line.find(separator, start);
    if (at == std::string_view::npos) {
      // A separator that ends the line (many exports end every line with one) closes the last
      // cell rather than opening an empty one.
      if (cells.empty() || !text::trim(line.substr(start)).empty())
        cells.push_back(line.substr(start));
      return cells;
    }
    cells.push_back(line.substr(start, at - start));
    start = at + 1;
  }
}

std::string_view unquote(std::string_view cell) {
  cell = text::trim(cell);
  if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"')
    cell = text::trim(cell.substr(1, cell.size() - 2));
  return cell;
}

enum class NumberStatus { kOk, kNotNumber, kOutOfRange, kNotFinite };

NumberStatus parse_number(std::string_view cell, char decimal_mark, double& value) {
  cell = unquote(cell);
  if (cell.empty()) return NumberStatus::kNotNumber;
  if (cell.size() > 1 && cell.front() == '+') cell.remove_prefix(1);  // from_chars refuses '+'
  char buffer[128];
  if (decimal_mark != '.') {
    if (cell.size() > sizeof buffer) return NumberStatus::kNotNumber;
    for (std::size_t i = 0; i < cell.size(); ++i) {
      if (cell[i] == '.') return NumberStatus::kNotNumber;  // '.' is no decimal mark here
      buffer[i] = cell[i] == decimal_mark ? '.' : cell[i];
    }
    cell = std::string_view(buffer, cell.size());
  }
  const char* last = cell.data() + cell.size();
  const std::from_chars_result result = std::from_chars(cell.data(), last, value);
  if (result.ptr != last) return NumberStatus::kNotNumber;
  if (result.ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (result.ec != std::errc()) return NumberStatus::kNotNumber;
  if (!std::isfinite(value)) return NumberStatus::kNotFinite;
  return NumberStatus::kOk;
}

bool numeric_row(std::string_view line, const Layout& layout, std::size_t& fields) {
  const std::vector<std::string_view> cells = split(line, layout.separator);
  double ignored = 0.0;
  for (std::string_view cell : cells)
    if (parse_number(cell, layout.decimal_mark, ignored) != NumberStatus::kOk) return false;
  fields = cells.size();
  return true;
}

// What one layout makes of the lines: where the numbers start, how many columns, and how far
// the rows follow it.
struct Candidate {
  Layout layout{',', '.'};
  std::size_t first_data = 0;  // 0-based line index
  std::size_t columns = 0;
  std::size_t rows = 0;      // consistent numeric rows from first_data on
  std::size_t bad_line = 0;  // 0-based index of the first row that breaks it; 0: none
  bool found = false;
  bool complete = false;
};

Candidate try_layout(const std::vector<std::string_view>& lines, const Layout& layout) {
  Candidate candidate;
  candidate.layout = layout;
  std::size_t index = 0;
  for (; index < lines.size(); ++index) {
    if (text::trim(lines[index]).empty()) continue;
    if (numeric_row(lines[index], layout, candidate.columns)) break;
  }
  if (index == lines.size()) return candidate;
  candidate.found = true;
  candidate.first_data = index;
  for (; index < lines.size(); ++index) {
    if (text::trim(lines[index]).empty()) continue;
    std::size_t fields = 0;
    if (!numeric_row(lines[index], layout, fields) || fields != candidate.columns) {
      candidate.bad_line = index;
      return candidate;
    }
    ++candidate.rows;
  }
  candidate.complete = true;
  return candidate;
}

bool better(const Candidate& a, const Candidate& b) {
  if (a.complete != b.complete) return a.complete;
  if (a.complete) return a.columns > b.columns;
  return a.rows > b.rows;
}

std::string separator_name(char separator) {
  switch (separator) {
    case ',':
      return "','";
    case ';':
      return "';'";
    case '\t':
      return "tab";
    default:
      return "blanks";
  }
}

}  // namespace

NameAndUnit split_name_and_unit(std::string_view cell) {
  cell = unquote(cell);
  if (!cell.empty() && (cell.back() == ']' || cell.back() == ')')) {
    const char open = cell.back() == ']' ? '[' : '(';
    const std::size_t at = cell.rfind(open);
    if (at != std::string_view::npos && at > 0) {
      const std::string_view name = text::trim(cell.substr(0, at));
      const std::string_view unit = text::trim(cell.substr(at + 1, cell.size() - at - 2));
      if (!name.empty()) return {std::string(name), std::string(unit)};
    }
  }
  return {std::string(cell), std::string()};
}

DelimitedTable parse_delimited_text(std::string_view bytes, const std::string& path) {
  const std::vector<std::string_view> lines = text::split_lines(bytes);
  Candidate best;
  for (const Layout& layout : kLayouts) {
    const Candidate candidate = try_layout(lines, layout);
    if (!candidate.found) continue;
    if (!best.found || better(candidate, best)) best = candidate;
  }
  if (!best.found) {
    throw HostError(path +
                    ": no rows of numbers (expected a table separated by ',', ';', tab or "
                    "blanks, under an optional header line)");
  }
  const Layout layout = best.layout;
  if (!best.complete) {
    // The message names the first cell that breaks the layout the most rows follow.
    const std::size_t line = best.bad_line;
    const std::vector<std::string_view> cells = split(lines[line], layout.separator);
    std::string what;
    if (cells.size() != best.columns) {
      what = "expected " + std::to_string(best.columns) + " fields separated by " +
             separator_name(layout.separator) + " like line " +
             std::to_string(best.first_data + 1) + ", found " + std::to_string(cells.size());
    } else {
      for (std::size_t column = 0; column < cells.size(); ++column) {
        double value = 0.0;
        const NumberStatus status = parse_number(cells[column], layout.decimal_mark, value);
        if (status == NumberStatus::kOk) continue;
        what = "column " + std::to_string(column + 1) + ": " + text::quoted(unquote(cells[column]));
        what += status == NumberStatus::kOutOfRange ? " is out of the range of a double"
                : status == NumberStatus::kNotFinite
                    ? " is not a finite number"
                    : std::string(" is not a number (decimal mark '") + layout.decimal_mark + "')";
        break;
      }
    }
    text::fail(path, line + 1, what);
  }

  DelimitedTable table;
  table.path = path;
  table.separator = layout.separator;
  table.decimal_mark = layout.decimal_mark;
  table.first_data_line = best.first_data + 1;
  table.channels.resize(best.columns);
  for (std::size_t column = 0; column < best.columns; ++column)
    table.channels[column].name = "column " + std::to_string(column + 1);
  // The header is the last non-blank line above the numbers if it has one cell per column;
  // anything above it (banners, '#' comments) is skipped.
  for (std::size_t index = best.first_data; index-- > 0;) {
    if (text::trim(lines[index]).empty()) continue;
    const std::vector<std::string_view> cells = split(lines[index], layout.separator);
    if (cells.size() == best.columns) {
      table.header_line = index + 1;
      for (std::size_t column = 0; column < cells.size(); ++column) {
        NameAndUnit parsed = split_name_and_unit(cells[column]);
        if (parsed.name.empty()) continue;
        table.channels[column].name = std::move(parsed.name);
        table.channels[column].unit = std::move(parsed.unit);
      }
      for (std::size_t a = 0; a < best.columns; ++a)
        for (std::size_t b = a + 1; b < best.columns; ++b)
          if (table.channels[a].name == table.channels[b].name)
            text::fail(path, index + 1,
                       "column '" + table.channels[a].name + "' appears twice in the header");
    }
    break;
  }
  for (TextChannel& channel : table.channels) channel.values.reserve(best.rows);
  table.row_lines.reserve(best.rows);
  for (std::size_t index = best.first_data; index < lines.size(); ++index) {
    if (text::trim(lines[index]).empty()) continue;
    table.row_lines.push_back(index + 1);
    const std::vector<std::string_view> cells = split(lines[index], layout.separator);
    for (std::size_t column = 0; column < cells.size(); ++column) {
      double value = 0.0;
      parse_number(cells[column], layout.decimal_mark, value);  // checked by try_layout
      table.channels[column].values.push_back(value);
    }
  }
  return table;
}

DelimitedTable read_delimited_text(const std::string& path) {
  const std::string bytes = text::read_file(path);
  return parse_delimited_text(bytes, path);
}

const TextChannel& DelimitedTable::channel(std::string_view selector) const {
  for (const TextChannel& candidate : channels)
    if (candidate.name == selector) return candidate;
  const auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c + 32) : c; };
  for (const TextChannel& candidate : channels) {
    if (candidate.name.size() != selector.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < selector.size() && same; ++i)
      same = lower(candidate.name[i]) == lower(selector[i]);
    if (same) return candidate;
  }
  std::size_t index = 0;
  const auto result = std::from_chars(selector.data(), selector.data() + selector.size(), index);
  if (result.ec == std::errc() && result.ptr == selector.data() + selector.size() && index >= 1 &&
      index <= channels.size()) {
    return channels[index - 1];
  }
  std::string names;
  for (std::size_t i = 0; i < channels.size(); ++i) {
    names += (i == 0 ? "" : ", ") + std::to_string(i + 1) + " '" + channels[i].name + "'";
    if (!channels[i].unit.empty()) names += " [" + channels[i].unit + "]";
  }
  throw HostError(path + ": no column " + text::quoted(selector) + " (the columns: " + names + ")");
}

}  // namespace stickslip::host
