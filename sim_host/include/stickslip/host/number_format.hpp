// Full-precision number output for CSV files: exactly what printf("%.17g") prints, so every double
// reads back to the same bits. fmt's "{:.17g}" costs ~240 ns per value, which made writing a
// 1e7-row, 7-column file take ~15 s; this exact fast path (~25 ns) falls back to fmt only where
// it cannot prove the rounding (ties, huge or tiny magnitudes, non-finite values).
#pragma once

#include <cstddef>

namespace stickslip::host {

// Longest output: "-2.2250738585072014e-308" (24 characters) plus room.
inline constexpr std::size_t kMaxG17Chars = 32;

// Writes `value` as "%.17g" would at `out` (at least kMaxG17Chars free) and returns the end.
char* format_g17(double value, char* out) noexcept;

}  // namespace stickslip::host
