// The Vector ASC reader on arbitrary bytes: it returns frames that keep the promises of
// host/io/can_log.hpp or throws one HostError line naming the file; nothing else.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"

#include "fuzz_can_logs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    stickslip::fuzz::check_log(stickslip::host::parse_asc(bytes, "in.asc"));
  } catch (const stickslip::host::HostError& error) {
    const std::string_view message = error.what();
    stickslip::fuzz::check(message.rfind("in.asc:", 0) == 0);
    stickslip::fuzz::check(message.find('\n') == std::string_view::npos);
  }
  return 0;
}
