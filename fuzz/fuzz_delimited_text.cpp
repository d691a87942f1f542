// The delimited text reader on arbitrary bytes: it returns channels of equal length holding
// finite numbers, or throws one HostError line naming the file; nothing else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/delimited_text.hpp"

#include "fuzz_support.hpp"

using stickslip::fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const stickslip::host::DelimitedTable table =
        stickslip::host::parse_delimited_text(text, "in.csv");
    check(!table.channels.empty());
    for (const auto& channel : table.channels) {
      check(channel.values.size() == table.channels[0].values.size());
      for (const double value : channel.values) check(std::isfinite(value));
    }
  } catch (const stickslip::host::HostError& error) {
    const std::string_view message = error.what();
    check(message.rfind("in.csv", 0) == 0);
    check(message.find('\n') == std::string_view::npos);
  }
  return 0;
}
