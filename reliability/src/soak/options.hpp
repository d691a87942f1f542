// What one soak run does: how long, in which scalar, through which path, how often it reports,
// and which check it makes fail on purpose.
#pragma once

#include <cstdint>

namespace stickslip::soak {

enum class Fault {
  none,
  nan,    // one per-sample output replaced by NaN before the finiteness check
  count,  // the observer is given one sample twice (a lost tick of the time keeping)
  stats   // one block of the window recomputation scaled by 1.01 (a statistics error of 1e-3)
};

struct Options {
  std::uint64_t samples = 1000000000ull;
  bool in_float = true;
  bool observer = true;
  int checkpoints = 10;
  const char* csv = nullptr;
  Fault fault = Fault::none;
};

}  // namespace stickslip::soak
