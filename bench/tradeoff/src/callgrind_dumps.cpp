#include "tradeoff/callgrind_dumps.hpp"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff {
namespace {

const std::string kTrigger = "desc: Trigger: Client Request: ";
const std::string kTotals = "totals: ";

// Names may be compressed: "(id) name" defines the id, "(id)" alone refers back to it.
std::string expand_name(std::map<std::string, std::string>& names, const std::string& value) {
  if (value.empty() || value[0] != '(') return value;
  const std::size_t close = value.find(')');
  const std::string id = value.substr(0, close + 1);
  if (close + 2 < value.size()) names[id] = value.substr(close + 2);
  return names[id];
}

// Self cost per source line and per function. Call cost lines (the line after "calls=") are
// inclusive and skipped; relative positions (+n, -n, *) follow the last cost line, which a call's
// destination does not change.
class SelfCostReader {
 public:
  explicit SelfCostReader(CallgrindDump& dump) : dump_(dump) {}

  void line(const std::string& line) {
    const std::size_t eq = line.find('=');
    const std::string key = eq == std::string::npos ? std::string() : line.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : line.substr(eq + 1);
    if (key == "fl") {
      function_file_ = file_ = expand_name(files_, value);
    } else if (key == "fi" || key == "fe") {
      file_ = expand_name(files_, value);
    } else if (key == "cfi" || key == "cfl") {
      expand_name(files_, value);
    } else if (key == "fn") {
      function_ = expand_name(functions_, value);
      file_ = function_file_;
    } else if (key == "cfn") {
      expand_name(functions_, value);
    } else if (key == "calls") {
      call_cost_next_ = true;
    } else if (key.empty() && (std::isdigit(static_cast<unsigned char>(line[0])) ||
                               line[0] == '+' || line[0] == '-' || line[0] == '*')) {
      cost(line);
    }
  }

 private:
  void cost(const std::string& line) {
    std::istringstream cost(line);
    std::string position;
    double ir = 0.0;
    cost >> position >> ir;
    if (position[0] == '+' || position[0] == '-') {
      last_ += std::strtol(position.c_str(), nullptr, 10);
    } else if (position != "*") {
      last_ = std::strtol(position.c_str(), nullptr, 10);
    }
    if (call_cost_next_) {
      call_cost_next_ = false;
      return;
    }
    dump_.lines[{file_, last_}] += ir;
    dump_.functions[function_] += ir;
    dump_.self_total += ir;
  }

  CallgrindDump& dump_;
  std::map<std::string, std::string> files_, functions_;
  std::string function_, function_file_, file_;
  long last_ = 0;
  bool call_cost_next_ = false;
};

}  // namespace

CallgrindDump read_callgrind_dump(const std::string& path, CallgrindDetail detail) {
  CallgrindDump dump;
  std::ifstream in(path);
  if (path.empty() || !in) return dump;
  SelfCostReader costs(dump);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(kTrigger, 0) == 0) {
      dump.trigger = line.substr(kTrigger.size());
      const std::size_t hash = line.rfind('#');
      if (hash != std::string::npos) dump.steps = std::strtod(line.c_str() + hash + 1, nullptr);
      continue;
    }
    if (line.rfind(kTotals, 0) == 0) {
      dump.totals = std::strtod(line.c_str() + kTotals.size(), nullptr);
      continue;
    }
    if (detail == CallgrindDetail::self_costs && !line.empty()) costs.line(line);
  }
  return dump;
}

std::map<std::string, double> read_instruction_counts(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::directory_iterator files(directory, error);
  if (error)
    throw host::HostError(directory + ": cannot read the callgrind dumps: " + error.message());
  std::map<std::string, double> counts;
  bool any_nonzero = false;
  for (const fs::directory_entry& entry : files) {
    if (!entry.is_regular_file()) continue;
    const CallgrindDump dump = read_callgrind_dump(entry.path().string(), CallgrindDetail::totals);
    const std::string& name = dump.trigger;
    const std::size_t hash = name.rfind('#');
    if (name.empty() || hash == std::string::npos || dump.totals < 0.0) continue;
    const double steps = std::strtod(name.c_str() + hash + 1, nullptr);
    if (!(steps > 0.0)) continue;
    counts[name.substr(0, hash)] = dump.totals / steps;
    any_nonzero = any_nonzero || dump.totals > 0.0;
  }
  if (counts.empty() || !any_nonzero) {
    throw host::HostError(directory +
                          ": no callgrind dump with instruction counts (run the harness under "
                          "valgrind --tool=callgrind --instr-atstart=no)");
  }
  return counts;
}

}  // namespace stickslip::tradeoff
