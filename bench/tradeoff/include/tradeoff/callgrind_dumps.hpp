// Callgrind's dump files, read by one parser for both uses: the instructions per step of every
// combination that count-instructions ran (a directory of dumps, each triggered by a client request
// named "<combination key>#<steps>", see count_library()), and the self cost per source line and
// per function of the one profiled configuration that the report breaks down.
#pragma once

#include <map>
#include <string>
#include <utility>

namespace stickslip::tradeoff {

// What one dump holds. "positions: line" (callgrind's default) and the first event (Ir) only.
struct CallgrindDump {
  std::string trigger;   // the client request's name, "<combination key>#<steps>"; empty if none
  double totals = -1.0;  // the "totals:" line; negative if the dump has none
  // From here on filled only when the self costs are asked for.
  double steps = 0.0;       // the number after the trigger's last '#'; 0 if none
  double self_total = 0.0;  // the sum of all self costs
  std::map<std::pair<std::string, long>, double> lines;  // (file, line) -> self Ir
  std::map<std::string, double> functions;               // function -> self Ir
};

enum class CallgrindDetail {
  totals,     // trigger and totals only (thousands of dumps, one figure each)
  self_costs  // and the self cost per source line and per function
};

// An unreadable file or an empty path gives an empty dump (no trigger, no totals).
CallgrindDump read_callgrind_dump(const std::string& path, CallgrindDetail detail);

// Key -> instructions per step. Throws host::HostError if the directory cannot be read or holds no
// dump at all (a run that forgot --instr-atstart=no counts nothing).
std::map<std::string, double> read_instruction_counts(const std::string& directory);

}  // namespace stickslip::tradeoff
