// The DBC reader on arbitrary bytes: it returns messages whose signals fit a 64-byte frame and
// decode (from the input's own bytes) to finite values, or throws one HostError line naming the
// file; nothing else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/dbc.hpp"

#include "fuzz_support.hpp"

using stickslip::fuzz::check;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  stickslip::host::Dbc dbc;
  try {
    dbc = stickslip::host::parse_dbc(text, "in.dbc");
  } catch (const stickslip::host::HostError& error) {
    const std::string_view message = error.what();
    check(message.rfind("in.dbc:", 0) == 0);
    check(message.find('\n') == std::string_view::npos);
    return 0;
  }
  std::uint8_t frame[64] = {};
  std::memcpy(frame, data, size < sizeof frame ? size : sizeof frame);
  for (const stickslip::host::DbcMessage& message : dbc.messages) {
    check(message.id <= (message.extended ? 0x1FFFFFFFu : 0x7FFu));
    for (const stickslip::host::DbcSignal& signal : message.signals) {
      check(signal.length_bits >= 1 && signal.length_bits <= 64);
      check(signal.bytes_needed >= 1 && signal.bytes_needed <= 64);
      check(!stickslip::host::decode_signal(signal, frame, signal.bytes_needed - 1u).has_value());
      const auto value = stickslip::host::decode_signal(signal, frame, sizeof frame);
      check(value.has_value());
      // Finite factor and offset times a raw value of at most 64 bits may still overflow to
      // infinity (a factor of 1e300); only NaN would mean a broken decode.
      check(!std::isnan(*value));
    }
  }
  return 0;
}
