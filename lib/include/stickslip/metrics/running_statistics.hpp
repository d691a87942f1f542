// Streaming, allocation-free statistics of a run: RMS of a_u and a_x, acceleration
// transmissibility T_ax = RMS(a_x)/RMS(a_u), stick probability p = time stuck / total time.
#pragma once

#include <cmath>
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

template <typename T>
class RunningStatistics {
 public:
  void reset() noexcept {
    sum_u_sq_.reset();
    sum_x_sq_.reset();
    stuck_time_s_.reset();
    samples_ = 0;
    steps_ = 0;
  }
  // One output sample (every row of a run, the initial one included).
  void add_sample(T a_u, T a_x) noexcept {
    sum_u_sq_.add(a_u * a_u);
    sum_x_sq_.add(a_x * a_x);
    ++samples_;
  }
  // One step of length dt with the time it spent stuck.
  void add_step(T stuck_time_s) noexcept {
    stuck_time_s_.add(stuck_time_s);
    ++steps_;
  }

  std::uint64_t samples() const noexcept { return samples_; }
  std::uint64_t steps() const noexcept { return steps_; }
  // Reporting (not per sample): plain double arithmetic.
  double rms_u() const noexcept { return rms(sum_u_sq_); }
  double rms_x() const noexcept { return rms(sum_x_sq_); }
  // T_ax; 0 when the input is identically zero (no transmissibility to speak of).
  double transmissibility() const noexcept {
    const double u = rms_u();
    return u > 0.0 ? rms_x() / u : 0.0;
  }
  double stuck_time_s() const noexcept { return ScalarTraits<T>::to_double(stuck_time_s_.value()); }
  // p = time stuck / total time; `dt_s` is the step of the run.
  double stick_probability(double dt_s) const noexcept {
    const double total = static_cast<double>(steps_) * dt_s;
    return total > 0.0 ? stuck_time_s() / total : 0.0;
  }

 private:
  double rms(const CompensatedSum<T>& sum) const noexcept {
    if (samples_ == 0) return 0.0;
    return std::sqrt(ScalarTraits<T>::to_double(sum.value()) / static_cast<double>(samples_));
  }

  CompensatedSum<T> sum_u_sq_, sum_x_sq_, stuck_time_s_;
  std::uint64_t samples_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace stickslip
