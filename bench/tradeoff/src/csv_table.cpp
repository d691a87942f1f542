#include "tradeoff/csv_table.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <ostream>

#include <fmt/format.h>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff {
namespace {

struct Column {
  const char* name;
  std::function<std::string(const Row&)> get;
  std::function<void(Row&, const std::string&)> set;
};

// RFC 4180: a cell with a separator or a quote is quoted, quotes doubled; line breaks become
// spaces.
std::string clean(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

std::string number(double value) {
  if (!std::isfinite(value)) return {};
  return fmt::format("{:.5g}", value);
}

double parse_double(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') throw host::HostError("'" + text + "' is not a number");
  return value;
}

Column text(const char* name, std::string Row::*member) {
  return {name, [member](const Row& r) { return clean(r.*member); },
          [member](Row& r, const std::string& v) { r.*member = v; }};
}
Column real(const char* name, double Row::*member) {
  return {name, [member](const Row& r) { return number(r.*member); },
          [member](Row& r, const std::string& v) { r.*member = parse_double(v); }};
}
Column optional(const char* name, std::optional<double> Row::*member) {
  return {name,
          [member](const Row& r) { return (r.*member) ? number(*(r.*member)) : std::string(); },
          [member](Row& r, const std::string& v) {
            if (v.empty()) {
              (r.*member).reset();
            } else {
              r.*member = parse_double(v);
            }
          }};
}

const std::vector<Column>& columns() {
  static const std::vector<Column> all = {
      text("scene", &Row::scene),
      text("kind", &Row::kind),
      text("friction", &Row::friction),
      real("K", &Row::den_hartog_k),
      real("b_ns_per_m", &Row::damping_ns_per_m),
      real("ffk_n", &Row::kinetic_friction_n),
      real("ffs_n", &Row::static_friction_n),
      real("duration_s", &Row::duration_s),
      text("implementation", &Row::implementation),
      text("model", &Row::model),
      text("integrator", &Row::integrator),
      optional("tolerance", &Row::tolerance),
      text("scalar", &Row::scalar),
      real("dt_ms", &Row::dt_ms),
      {"steps", [](const Row& r) { return std::to_string(r.steps); },
       [](Row& r, const std::string& v) { r.steps = static_cast<std::uint64_t>(parse_double(v)); }},
      text("status", &Row::status),
      optional("ns_per_sample_median", &Row::ns_median),
      optional("ns_per_sample_min", &Row::ns_min),
      optional("ns_per_sample_max", &Row::ns_max),
      optional("repetitions", &Row::repetitions),
      optional("instructions_per_sample", &Row::ir_per_sample),
      optional("t_ax", &Row::t_ax),
      optional("t_ax_ref", &Row::t_ax_ref),
      optional("t_ax_rel_err", &Row::t_ax_rel_err),
      optional("p", &Row::p),
      optional("p_ref", &Row::p_ref),
      optional("p_abs_err", &Row::p_abs_err),
      optional("a_x_rms_err", &Row::a_x_rms_err),
      optional("a_x_rms_err_rel", &Row::a_x_rms_err_rel),
      optional("x_r_rms_err", &Row::x_r_rms_err),
      optional("x_r_rms_err_rel", &Row::x_r_rms_err_rel),
      optional("solver_t_ax_rel_err", &Row::solver_t_ax_rel_err),
      optional("solver_a_x_rms_err_rel", &Row::solver_a_x_rms_err_rel),
      optional("solver_x_r_rms_err_rel", &Row::solver_x_r_rms_err_rel),
      optional("events", &Row::events),
      text("note", &Row::note),
  };
  return all;
}

}  // namespace

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cells.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}

std::string Row::configuration() const {
  if (implementation == "odeint") {
    return tolerance ? fmt::format("{} tol {:g}", integrator, *tolerance) : integrator;
  }
  return model + "/" + integrator + "/" + scalar;
}

std::vector<std::string> column_names() {
  std::vector<std::string> names;
  for (const Column& c : columns()) names.emplace_back(c.name);
  return names;
}

void write_header(std::ostream& out) {
  const auto& all = columns();
  for (std::size_t i = 0; i < all.size(); ++i) out << (i ? "," : "") << all[i].name;
  out << '\n';
}

void write_row(std::ostream& out, const Row& row) {
  const auto& all = columns();
  for (std::size_t i = 0; i < all.size(); ++i) out << (i ? "," : "") << all[i].get(row);
  out << '\n';
}

std::vector<Row> read_rows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw host::HostError(path + ": cannot open");
  std::string line;
  if (!std::getline(in, line)) throw host::HostError(path + ": empty file");
  const std::vector<std::string> header = split_csv_line(line);
  const auto& all = columns();
  std::vector<int> index(all.size(), -1);
  for (std::size_t c = 0; c < all.size(); ++c) {
    for (std::size_t h = 0; h < header.size(); ++h) {
      if (header[h] == all[c].name) index[c] = static_cast<int>(h);
    }
    if (index[c] < 0) throw host::HostError(path + ":1: column '" + all[c].name + "' is missing");
  }
  std::vector<Row> rows;
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() != header.size()) {
      throw host::HostError(fmt::format("{}:{}: {} cells, the header has {}", path, line_number,
                                        cells.size(), header.size()));
    }
    Row row;
    for (std::size_t c = 0; c < all.size(); ++c) {
      try {
        all[c].set(row, cells[static_cast<std::size_t>(index[c])]);
      } catch (const host::HostError& error) {
        throw host::HostError(
            fmt::format("{}:{}: column '{}': {}", path, line_number, all[c].name, error.what()));
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace stickslip::tradeoff
