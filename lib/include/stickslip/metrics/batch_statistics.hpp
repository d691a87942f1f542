// RunningStatistics for the N lanes of a batch (models/batch.hpp), as structure of arrays so that
// the per-sample adds vectorise. Every lane's figures equal those of a RunningStatistics fed with
// the same samples, bit for bit: the same block sums, folded at the same samples.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/metrics/running_statistics.hpp"

namespace stickslip {

template <typename T, std::size_t N>
class BatchStatistics {
  static_assert(N >= 1, "a batch has at least one lane");

 public:
  void reset() noexcept {
    for (std::size_t i = 0; i < N; ++i) {
      total_u_sq_[i].reset();
      total_x_sq_[i].reset();
      total_stuck_[i].reset();
      block_u_sq_[i] = block_x_sq_[i] = block_stuck_[i] = T(0);
    }
    in_block_ = 0;
    samples_ = 0;
    steps_ = 0;
  }
  // One output sample of every lane (as RunningStatistics::add_sample, lane by lane). The
  // samples are copied first: the sums then cannot alias them, and the loops vectorise without
  // a run-time overlap test.
  void add_sample(const T* a_u, const T* a_x) noexcept {
    T u[N], x[N];
    for (std::size_t i = 0; i < N; ++i) u[i] = a_u[i];
    for (std::size_t i = 0; i < N; ++i) x[i] = a_x[i];
    for (std::size_t i = 0; i < N; ++i) {
      block_u_sq_[i] += u[i] * u[i];
      block_x_sq_[i] += x[i] * x[i];
    }
    count_sample();
  }
  // The same input sample for every lane.
  void add_sample(T a_u, const T* a_x) noexcept {
    const T u_sq = a_u * a_u;
    T x[N];
    for (std::size_t i = 0; i < N; ++i) x[i] = a_x[i];
    for (std::size_t i = 0; i < N; ++i) {
      block_u_sq_[i] += u_sq;
      block_x_sq_[i] += x[i] * x[i];
    }
    count_sample();
  }
  // One step of every lane, with the fraction of it spent stuck.
  void add_step(const T* stuck_fraction) noexcept {
    T f[N];
    for (std::size_t i = 0; i < N; ++i) f[i] = stuck_fraction[i];
    for (std::size_t i = 0; i < N; ++i) block_stuck_[i] += f[i];
    ++steps_;
  }

  // The statistics of one lane, as a RunningStatistics (for its reporting functions).
  RunningStatistics<T> lane(std::size_t index) const noexcept {
    RunningStatistics<T> s;
    s.total_u_sq_ = total_u_sq_[index];
    s.total_x_sq_ = total_x_sq_[index];
    s.total_stuck_ = total_stuck_[index];
    s.block_u_sq_ = block_u_sq_[index];
    s.block_x_sq_ = block_x_sq_[index];
    s.block_stuck_ = block_stuck_[index];
    s.in_block_ = in_block_;
    s.samples_ = samples_;
    s.steps_ = steps_;
    return s;
  }

 private:
  void count_sample() noexcept {
    ++samples_;
    if (++in_block_ == RunningStatistics<T>::kBlockSamples) {
      for (std::size_t i = 0; i < N; ++i) {
        total_u_sq_[i].add(block_u_sq_[i]);
        total_x_sq_[i].add(block_x_sq_[i]);
        total_stuck_[i].add(block_stuck_[i]);
        block_u_sq_[i] = block_x_sq_[i] = block_stuck_[i] = T(0);
      }
      in_block_ = 0;
    }
  }

  alignas(64) T block_u_sq_[N]{};
  alignas(64) T block_x_sq_[N]{};
  alignas(64) T block_stuck_[N]{};
  CompensatedSum<T> total_u_sq_[N], total_x_sq_[N], total_stuck_[N];
  unsigned in_block_ = 0;
  std::uint64_t samples_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace stickslip
