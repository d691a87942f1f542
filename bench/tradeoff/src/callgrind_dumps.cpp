#include "tradeoff/callgrind_dumps.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "stickslip/host/error.hpp"

namespace stickslip::tradeoff {

std::map<std::string, double> read_instruction_counts(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::directory_iterator files(directory, error);
  if (error)
    throw host::HostError(directory + ": cannot read the callgrind dumps: " + error.message());
  static const std::string kTrigger = "desc: Trigger: Client Request: ";
  static const std::string kTotals = "totals: ";
  std::map<std::string, double> counts;
  bool any_nonzero = false;
  for (const fs::directory_entry& entry : files) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path());
    std::string line, name;
    double total = -1.0;
    while (std::getline(in, line)) {
      if (line.rfind(kTrigger, 0) == 0) name = line.substr(kTrigger.size());
      if (line.rfind(kTotals, 0) == 0) total = std::strtod(line.c_str() + kTotals.size(), nullptr);
    }
    const std::size_t hash = name.rfind('#');
    if (name.empty() || hash == std::string::npos || total < 0.0) continue;
    const double steps = std::strtod(name.c_str() + hash + 1, nullptr);
    if (!(steps > 0.0)) continue;
    counts[name.substr(0, hash)] = total / steps;
    any_nonzero = any_nonzero || total > 0.0;
  }
  if (counts.empty() || !any_nonzero) {
    throw host::HostError(directory +
                          ": no callgrind dump with instruction counts (run the harness under "
                          "valgrind --tool=callgrind --instr-atstart=no)");
  }
  return counts;
}

}  // namespace stickslip::tradeoff
