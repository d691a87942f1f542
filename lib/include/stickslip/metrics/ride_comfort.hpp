// Streaming ISO 2631-1 ride-comfort figures of the seat and the floor it stands on,
// allocation-free: frequency-weighted RMS (Wk vertical or Wd horizontal), running RMS with
// integration time tau (1 s by default, exponential as ISO 2631-1 eq. (2) defines it) and its
// maximum MTVV, the fourth power vibration dose value VDV = (integral a_w^4 dt)^(1/4) (m/s^1.75),
// the crest factor (peak |a_w| over the weighted RMS), and SEAT = weighted RMS of the seat over
// that of the floor.
//
// Per sample: two weighting cascades, a few multiply-adds, one compare; no division, no call (the
// exponential window's coefficient 1 - exp(-dt/tau) is computed in configure()). Roots and
// quotients only when a figure is read.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/metrics/iso2631_weighting.hpp"
#include "stickslip/metrics/running_statistics.hpp"

namespace stickslip {

template <typename T>
class RideComfort {
 public:
  static constexpr unsigned kBlockSamples = 256;  // plain partial sums, then compensated totals

  ConfigResult configure(ComfortWeighting weighting, double sample_rate_hz,
                         double running_rms_time_s = 1.0) noexcept {
    ConfigResult result = floor_filter_.configure(weighting, sample_rate_hz);
    if (!result.ok()) return result;
    seat_filter_.configure(weighting, sample_rate_hz);
    if (!std::isfinite(running_rms_time_s) || !(running_rms_time_s * sample_rate_hz >= 1.0)) {
      result.status = std::isfinite(running_rms_time_s) ? Status::out_of_range : Status::not_finite;
      result.message.append("running_rms_time_s = ")
          .append(running_rms_time_s)
          .append(" must be finite and at least one sample interval");
      return result;
    }
    dt_s_ = 1.0 / sample_rate_hz;
    window_gain_ = S::from_double(-std::expm1(-dt_s_ / running_rms_time_s));
    weighting_ = weighting;
    reset();
    return result;
  }

  void reset() noexcept {
    floor_filter_.reset();
    seat_filter_.reset();
    floor_sq_.reset();
    seat_sq_.reset();
    floor_4_.reset();
    seat_4_.reset();
    block_floor_sq_ = block_seat_sq_ = block_floor_4_ = block_seat_4_ = T(0);
    in_block_ = 0;
    samples_ = 0;
    running_ms_ = max_running_ms_ = seat_peak_ = T(0);
  }

  // One sample of the floor and seat accelerations (m/s^2, the axis the weighting is for).
  void add_sample(T a_floor, T a_seat) noexcept {
    const T floor_w = counted(floor_filter_.step(a_floor));
    const T seat_w = counted(seat_filter_.step(a_seat));
    const T floor_sq = floor_w * floor_w, seat_sq = seat_w * seat_w;
    block_floor_sq_ += floor_sq;
    block_seat_sq_ += seat_sq;
    block_floor_4_ += floor_sq * floor_sq;
    block_seat_4_ += seat_sq * seat_sq;
    running_ms_ += window_gain_ * (seat_sq - running_ms_);
    max_running_ms_ = running_ms_ > max_running_ms_ ? running_ms_ : max_running_ms_;
    const T magnitude = S::abs(seat_w);
    seat_peak_ = magnitude > seat_peak_ ? magnitude : seat_peak_;
    ++samples_;
    if (++in_block_ == kBlockSamples) flush();
  }

  std::uint64_t samples() const noexcept { return samples_; }
  ComfortWeighting weighting() const noexcept { return weighting_; }
  // Reporting (not per sample): plain double arithmetic.
  double floor_weighted_rms() const noexcept { return mean_root(floor_sq_, block_floor_sq_); }
  double seat_weighted_rms() const noexcept { return mean_root(seat_sq_, block_seat_sq_); }
  // SEAT: 0 when the floor is still.
  double seat_ratio() const noexcept {
    const double floor = floor_weighted_rms();
    return floor > 0.0 ? seat_weighted_rms() / floor : 0.0;
  }
  double seat_vdv() const noexcept {
    return std::sqrt(std::sqrt(total(seat_4_, block_seat_4_) * dt_s_));
  }
  double floor_vdv() const noexcept {
    return std::sqrt(std::sqrt(total(floor_4_, block_floor_4_) * dt_s_));
  }
  double seat_running_rms() const noexcept { return std::sqrt(S::to_double(running_ms_)); }
  double seat_mtvv() const noexcept { return std::sqrt(S::to_double(max_running_ms_)); }
  double seat_peak() const noexcept { return S::to_double(seat_peak_); }
  double seat_crest_factor() const noexcept {
    const double rms = seat_weighted_rms();
    return rms > 0.0 ? seat_peak() / rms : 0.0;
  }

 private:
  using S = ScalarTraits<T>;
  // A weighted sample whose fourth power would underflow (float: below 2^-31 = 4.7e-10 m/s^2,
  // double: 2^-255) counts as 0: its share of any RMS or VDV is nil, and the step raises no
  // underflow (the weighting's start-up gives such samples; the tests' IEEE754 plugin fails on
  // FE_UNDERFLOW and an ECU may trap it). One compare and select per sample.
  static constexpr T smallest_counted() noexcept {
    T value = T(1);
    if constexpr (std::numeric_limits<T>::is_iec559) {
      for (int e = 0; e < (1 - std::numeric_limits<T>::min_exponent) / 4; ++e) value *= T(0.5);
    } else {
      value = T(0);
    }
    return value;
  }
  static T counted(T weighted) noexcept {
    return S::abs(weighted) >= smallest_counted() ? weighted : T(0);
  }
  void flush() noexcept {
    floor_sq_.add(block_floor_sq_);
    seat_sq_.add(block_seat_sq_);
    floor_4_.add(block_floor_4_);
    seat_4_.add(block_seat_4_);
    block_floor_sq_ = block_seat_sq_ = block_floor_4_ = block_seat_4_ = T(0);
    in_block_ = 0;
  }
  static double total(const CompensatedSum<T>& sum, T block) noexcept {
    CompensatedSum<T> copy = sum;
    copy.add(block);
    return S::to_double(copy.value());
  }
  double mean_root(const CompensatedSum<T>& sum, T block) const noexcept {
    return samples_ > 0 ? std::sqrt(total(sum, block) / static_cast<double>(samples_)) : 0.0;
  }

  WeightingFilter<T> floor_filter_, seat_filter_;
  CompensatedSum<T> floor_sq_, seat_sq_, floor_4_, seat_4_;
  T block_floor_sq_{}, block_seat_sq_{}, block_floor_4_{}, block_seat_4_{};
  unsigned in_block_ = 0;
  std::uint64_t samples_ = 0;
  T window_gain_{};  // 1 - exp(-dt/tau)
  T running_ms_{}, max_running_ms_{}, seat_peak_{};
  double dt_s_ = 0.0;
  ComfortWeighting weighting_ = ComfortWeighting::wk;
};

}  // namespace stickslip
