#include "report/text.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff::report {

bool same_dt(double a, double b) {
  return std::fabs(a - b) <= 1e-9 * std::max(a, b);
}

std::string ns(double value) {
  return value >= 100.0 ? fmt::format("{:.0f}", value) : fmt::format("{:.1f}", value);
}
std::string sci(double value) {
  return value == 0.0 ? "0" : fmt::format("{:.1e}", value);
}
std::string opt_sci(const std::optional<double>& value) {
  return value ? sci(*value) : "–";
}
std::string percent(double band) {
  return fmt::format("{:g} %", band * 100.0);
}
std::string dt_label(double dt_ms) {
  return fmt::format("{:g} ms", dt_ms);
}
std::string times(double ratio) {
  return fmt::format("{:.1f}x", ratio);
}

std::string met(bool ok) {
  return ok ? "**met**" : "**missed**";
}

double median_of(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

std::string read_text(const std::string& path) {
  if (path.empty()) return {};
  std::ifstream in(path);
  if (!in) return {};
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::map<std::string, std::string> read_facts(const std::string& path) {
  std::map<std::string, std::string> facts;
  std::ifstream in(path);
  if (!in) throw host::HostError(path + ": cannot open the machine facts");
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    facts[line.substr(0, colon)] = value;
  }
  return facts;
}

std::string fact(const std::map<std::string, std::string>& facts, const std::string& key) {
  const auto found = facts.find(key);
  return found == facts.end() || found->second.empty() ? "unknown" : found->second;
}

void Table::write(std::ostream& out) const {
  out << "|";
  for (const auto& h : header) out << " " << h << " |";
  out << "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) out << "---|";
  out << "\n";
  for (const auto& row : rows) {
    out << "|";
    for (const std::string& c : row) {
      std::string escaped;  // a '|' inside a cell (code spans too) must be escaped in GFM tables
      for (const char ch : c) escaped += ch == '|' ? std::string("\\|") : std::string(1, ch);
      out << " " << escaped << " |";
    }
    out << "\n";
  }
  out << "\n";
}

}  // namespace stickslip::tradeoff::report
