// The `stickslip` command line, callable in-process (tests pass string streams).
//
// Exit status: 0 success; 1 bad input data or a failed file operation; 2 a command-line error
// (unknown option or subcommand, missing or invalid value). Errors are one line on `err`:
// "stickslip: <file>:<line>: <problem>" for file contents, "stickslip: <option>: <problem>" for
// options. run_cli never throws.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace stickslip::host {

int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err);

// run_cli on std::cout and std::cerr for the executable's main(): SIGINT and SIGTERM remove
// every temporary output, print one line and exit 130 / 143 (existing outputs stay as they were).
int run_cli_process(int argc, char** argv);

// The same, with the arguments after the program name.
int run_cli(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err);

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

}  // namespace stickslip::host
