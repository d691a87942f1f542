#include "stickslip/host/io/number_format.hpp"

#include <charconv>
#include <cmath>
#include <cstring>

namespace stickslip::host {

char* format_g17(double value, char* out) noexcept {
  if (!std::isfinite(value)) {  // printf's spelling, which to_chars does not share for NaN signs
    const char* text =
        std::isnan(value) ? (std::signbit(value) ? "-nan" : "nan") : (value < 0 ? "-inf" : "inf");
    const std::size_t length = std::strlen(text);
    std::memcpy(out, text, length);
    return out + length;
  }
  return std::to_chars(out, out + kMaxG17Chars, value, std::chars_format::general, 17).ptr;
}

}  // namespace stickslip::host
