// How the report writes numbers, reads its optional text inputs and lays out markdown tables.
#pragma once

#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace stickslip::tradeoff::report {

// dt values of the CSV are decimal text read back: equal within rounding.
bool same_dt(double a, double b);

std::string ns(double value);  // ns/sample: one decimal below 100
std::string sci(double value);
std::string opt_sci(const std::optional<double>& value);  // "–" when missing
std::string percent(double band);
std::string dt_label(double dt_ms);
std::string times(double ratio);  // "12.3x"
std::string met(bool ok);         // a target's verdict

double median_of(std::vector<double> values);  // NaN for none

// The whole file; empty for an empty path or an unreadable file (optional inputs).
std::string read_text(const std::string& path);
// "key: value" lines. Throws host::HostError if the file cannot be opened.
std::map<std::string, std::string> read_facts(const std::string& path);
// The value, or "unknown" when missing or empty.
std::string fact(const std::map<std::string, std::string>& facts, const std::string& key);

// A GitHub-flavoured markdown table, followed by an empty line.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  void write(std::ostream& out) const;
};

}  // namespace stickslip::tradeoff::report
