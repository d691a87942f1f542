// Placeholder until the candump log reader/writer lands.
#include "stickslip/host/candump_log.hpp"

#include "stickslip/host/error.hpp"

namespace stickslip::host {

std::vector<LoggedFrame> read_candump_log(const std::string& path) {
  throw HostError(path + ": candump logs are not supported yet");
}

void write_candump_log(const std::string& path, const std::vector<LoggedFrame>&) {
  throw HostError(path + ": candump logs are not supported yet");
}

}  // namespace stickslip::host
