// Instruction counts from callgrind's dump files: every file of a directory whose trigger is a
// client request named "<combination key>#<steps>" (see count_library()) gives the instructions
// (Ir) per step of that combination.
#pragma once

#include <map>
#include <string>

namespace stickslip::tradeoff {

// Key -> instructions per step. Throws host::HostError if the directory cannot be read or holds no
// dump at all (a run that forgot --instr-atstart=no counts nothing).
std::map<std::string, double> read_instruction_counts(const std::string& directory);

}  // namespace stickslip::tradeoff
