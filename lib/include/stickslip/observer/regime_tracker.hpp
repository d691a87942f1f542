// Den Hartog's friction regime of a stream, with hysteresis so that it does not flicker while K
// sits near a boundary: the regime changes only once K has crossed a boundary (0.4, 0.75) by more
// than the hysteresis margin. The first K seen sets the regime directly.
#pragma once

#include <cstdint>

#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip {

class RegimeTracker {
 public:
  RegimeTracker() noexcept { configure(0.05); }
  void configure(double hysteresis_k) noexcept {
    const double h = hysteresis_k > 0.0 ? hysteresis_k : 0.0;
    set(double_, h);
    set(float_, h);
    reset();
  }
  void reset() noexcept {
    known_ = false;
    regime_ = FrictionRegime::signum_suffices;
    changes_ = 0;
  }
  // Feeds the latest K (from a completed window block); returns the regime. R: double, or float
  // for an observer whose figures are float (no double arithmetic on an FPU without it).
  template <typename R>
  FrictionRegime update(R k) noexcept {
    if (!(k == k)) return regime_;  // NaN: keep what we have
    const Thresholds<R>& t = thresholds(R(0));
    FrictionRegime next = regime_;
    if (!known_) {
      next = friction_regime(k);
      known_ = true;
    } else if (k > t.high_up) {
      next = FrictionRegime::stick_slip_required;
    } else if (k < t.low_down) {
      next = FrictionRegime::signum_suffices;
    } else if ((regime_ == FrictionRegime::signum_suffices && k > t.low_up) ||
               (regime_ == FrictionRegime::stick_slip_required && k < t.high_down)) {
      next = FrictionRegime::transition;
    }
    changes_ += (known_ && next != regime_) ? 1u : 0u;
    regime_ = next;
    return regime_;
  }
  bool known() const noexcept { return known_; }
  FrictionRegime regime() const noexcept { return regime_; }
  std::uint32_t changes() const noexcept { return changes_; }

 private:
  // The boundaries moved by the hysteresis margin.
  template <typename R>
  struct Thresholds {
    R low_down, low_up, high_down, high_up;
  };
  template <typename R>
  static void set(Thresholds<R>& t, double h) noexcept {
    const double low = kSignumSufficesBelowK, high = kStickSlipRequiredAboveK;
    t = {R(low - h), R(low + h), R(high - h), R(high + h)};
  }
  const Thresholds<double>& thresholds(double) const noexcept { return double_; }
  const Thresholds<float>& thresholds(float) const noexcept { return float_; }

  Thresholds<double> double_{};
  Thresholds<float> float_{};
  FrictionRegime regime_ = FrictionRegime::signum_suffices;
  bool known_ = false;
  std::uint32_t changes_ = 0;
};

}  // namespace stickslip
