// Streaming, allocation-free statistics of a run: RMS of a_u and a_x, acceleration
// transmissibility T_ax = RMS(a_x)/RMS(a_u), stick probability p = time stuck / total time.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// Neumaier-compensated sum: the error stays at a few ulp of the total however many terms are
// added, so float runs of 1e9 samples keep their statistics.
template <typename T>
class CompensatedSum {
 public:
  void add(T value) noexcept {
    const T total = sum_ + value;
    if (ScalarTraits<T>::abs(sum_) >= ScalarTraits<T>::abs(value)) {
      compensation_ += (sum_ - total) + value;
    } else {
      compensation_ += (value - total) + sum_;
    }
    sum_ = total;
  }
  T value() const noexcept { return sum_ + compensation_; }
  void reset() noexcept { sum_ = compensation_ = T(0); }

 private:
  T sum_{};
  T compensation_{};
};

template <typename T, std::size_t N>
class BatchStatistics;

template <typename T>
class RunningStatistics {
 public:
  // Plain partial sums over blocks of this many samples, then folded into compensated totals:
  // one add per sample in the hot loop, error ~ (block + few) ulp however long the run.
  static constexpr unsigned kBlockSamples = 256;

  void reset() noexcept {
    total_u_sq_.reset();
    total_x_sq_.reset();
    total_stuck_.reset();
    block_u_sq_ = block_x_sq_ = block_stuck_ = T(0);
    in_block_ = 0;
    samples_ = 0;
    steps_ = 0;
  }
  // One output sample (every row of a run, the initial one included).
  void add_sample(T a_u, T a_x) noexcept {
    block_u_sq_ += a_u * a_u;
    block_x_sq_ += a_x * a_x;
    ++samples_;
    if (++in_block_ == kBlockSamples) flush();
  }
  // One step, with the fraction of it spent stuck (StepOutput::stuck_fraction, in [0, 1]).
  void add_step(T stuck_fraction) noexcept {
    block_stuck_ += stuck_fraction;
    ++steps_;
  }

  std::uint64_t samples() const noexcept { return samples_; }
  std::uint64_t steps() const noexcept { return steps_; }
  // Reporting (not per sample): plain double arithmetic.
  double rms_u() const noexcept { return rms(total_u_sq_, block_u_sq_); }
  double rms_x() const noexcept { return rms(total_x_sq_, block_x_sq_); }
  // T_ax; 0 when the input is identically zero (no transmissibility to speak of).
  double transmissibility() const noexcept {
    const double u = rms_u();
    return u > 0.0 ? rms_x() / u : 0.0;
  }
  // Time stuck, for a run with step `dt_s`.
  double stuck_time_s(double dt_s) const noexcept {
    return total(total_stuck_, block_stuck_) * dt_s;
  }
  // p = time stuck / total time.
  double stick_probability() const noexcept {
    return steps_ > 0 ? total(total_stuck_, block_stuck_) / static_cast<double>(steps_) : 0.0;
  }

 private:
  // A batch keeps the same sums for many lanes and hands out one lane's as a RunningStatistics.
  template <typename, std::size_t>
  friend class BatchStatistics;

  void flush() noexcept {
    total_u_sq_.add(block_u_sq_);
    total_x_sq_.add(block_x_sq_);
    total_stuck_.add(block_stuck_);
    block_u_sq_ = block_x_sq_ = block_stuck_ = T(0);
    in_block_ = 0;
  }
  static double total(const CompensatedSum<T>& sum, T block) noexcept {
    CompensatedSum<T> copy = sum;
    copy.add(block);
    return ScalarTraits<T>::to_double(copy.value());
  }
  double rms(const CompensatedSum<T>& sum, T block) const noexcept {
    if (samples_ == 0) return 0.0;
    return std::sqrt(total(sum, block) / static_cast<double>(samples_));
  }

  CompensatedSum<T> total_u_sq_, total_x_sq_, total_stuck_;
  T block_u_sq_{}, block_x_sq_{}, block_stuck_{};
  unsigned in_block_ = 0;
  std::uint64_t samples_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace stickslip
