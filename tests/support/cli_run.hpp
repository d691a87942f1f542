// The stickslip command run in this process, its output captured: what the command-line tests
// (tests/cli) drive. Apart from host_test_support.hpp so that a host-library test, which must not
// depend on the command line, cannot reach it.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "stickslip/host/cli/cli.hpp"

namespace stickslip::test {

struct CliRun {
  int status;
  std::string out;
  std::string err;
};

inline CliRun run_stickslip(const std::vector<std::string>& arguments) {
  std::ostringstream out, err;
  const int status = stickslip::host::run_cli(arguments, out, err);
  return {status, out.str(), err.str()};
}

}  // namespace stickslip::test
