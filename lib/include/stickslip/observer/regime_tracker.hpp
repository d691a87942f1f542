// Den Hartog's friction regime of a stream, with hysteresis so that it does not flicker while K
// sits near a boundary: the regime changes only once K has crossed a boundary (0.4, 0.75) by more
// than the hysteresis margin. The first K seen sets the regime directly.
#pragma once

#include <cstdint>

#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip {

class RegimeTracker {
 public:
  void configure(double hysteresis_k) noexcept {
    hysteresis_k_ = hysteresis_k > 0.0 ? hysteresis_k : 0.0;
    reset();
  }
  void reset() noexcept {
    known_ = false;
    regime_ = FrictionRegime::signum_suffices;
    changes_ = 0;
  }
  // Feeds the latest K (from a completed window block); returns the regime.
  FrictionRegime update(double k) noexcept {
    if (!(k == k)) return regime_;  // NaN: keep what we have
    FrictionRegime next = regime_;
    if (!known_) {
      next = friction_regime(k);
      known_ = true;
    } else {
      const double low = kSignumSufficesBelowK, high = kStickSlipRequiredAboveK, h = hysteresis_k_;
      if (k > high + h) {
        next = FrictionRegime::stick_slip_required;
      } else if (k < low - h) {
        next = FrictionRegime::signum_suffices;
      } else if ((regime_ == FrictionRegime::signum_suffices && k > low + h) ||
                 (regime_ == FrictionRegime::stick_slip_required && k < high - h)) {
        next = FrictionRegime::transition;
      }
    }
    changes_ += (known_ && next != regime_) ? 1u : 0u;
    regime_ = next;
    return regime_;
  }
  bool known() const noexcept { return known_; }
  FrictionRegime regime() const noexcept { return regime_; }
  std::uint32_t changes() const noexcept { return changes_; }

 private:
  double hysteresis_k_ = 0.05;
  FrictionRegime regime_ = FrictionRegime::signum_suffices;
  bool known_ = false;
  std::uint32_t changes_ = 0;
};

}  // namespace stickslip
