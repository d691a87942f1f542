// The scaling of a DBC signal from the text of its factor and offset (dbc.cpp's parser).
#pragma once

#include <string_view>

#include "stickslip/host/io/dbc.hpp"

namespace stickslip::host {

// factor and offset as parsed; exact (one rounding) when both decimals have a common power-of-ten
// denominator a double holds, as a decimal-arithmetic decoder computes.
DbcScale make_scale(std::string_view factor_text, std::string_view offset_text, double factor,
                    double offset);

}  // namespace stickslip::host
