// The stickslip command: everything lives in the stickslip_host library, which tests call too.
#include <iostream>

#include "stickslip/host/cli/cli.hpp"

int main(int argc, char** argv) {
  std::ios::sync_with_stdio(false);
  return stickslip::host::run_cli_process(argc, argv);
}
