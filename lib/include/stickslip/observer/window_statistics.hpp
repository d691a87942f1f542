// Windowed statistics of a stream, allocation-free: a block window (the last kBlocks completed
// blocks of a fixed number of samples each; capacity a template parameter) and an exponential
// window (time constant tau), both of mean squares of a_u and a_x, stuck time and the events.
// Per sample: a few adds (block) and multiply-adds (exponential); nothing else. A block's sums are
// folded into the window when the block completes, by recomputing the window's totals from its
// kBlocks blocks (no running subtraction, so nothing drifts however long the run).
#pragma once

#include <cstddef>
#include <cstdint>

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// The sums one block (and the window) holds.
template <typename T>
struct WindowSums {
  T u_sq{}, x_sq{}, stuck{};  // sum of a_u^2, a_x^2 (m^2/s^4), and stuck fractions
  T residual_sq{};            // sum of (a_x,measured - a_x,model)^2 where measured
  std::uint32_t samples = 0, steps = 0, measured = 0;
  std::uint32_t stick_events = 0;  // steps that ended stuck after slipping
  std::uint32_t slip_events = 0;   // steps that ended slipping after being stuck (break-away)
};

template <typename T, std::size_t kBlocks>
class BlockWindow {
  static_assert(kBlocks >= 2, "a block window needs at least two blocks");

 public:
  // samples_per_block >= 1: the window is kBlocks * samples_per_block samples long.
  void configure(std::uint32_t samples_per_block) noexcept {
    samples_per_block_ = samples_per_block < 1 ? 1 : samples_per_block;
    reset();
  }
  void reset() noexcept {
    current_ = WindowSums<T>{};
    window_ = WindowSums<T>{};
    for (auto& b : blocks_) b = WindowSums<T>{};
    next_ = 0;
    filled_ = 0;
  }
  // Returns true when this sample completed a block (the window's totals changed).
  bool add(T a_u, T a_x, T stuck_fraction, bool step, bool measured, T residual, bool stick_event,
           bool slip_event) noexcept {
    current_.u_sq += a_u * a_u;
    current_.x_sq += a_x * a_x;
    current_.stuck += stuck_fraction;
    current_.residual_sq += residual * residual;
    current_.measured += measured ? 1u : 0u;
    current_.steps += step ? 1u : 0u;
    current_.stick_events += stick_event ? 1u : 0u;
    current_.slip_events += slip_event ? 1u : 0u;
    if (++current_.samples < samples_per_block_) return false;
    blocks_[next_] = current_;
    next_ = next_ + 1 == kBlocks ? 0 : next_ + 1;
    filled_ += filled_ < kBlocks ? 1u : 0u;
    current_ = WindowSums<T>{};
    WindowSums<T> total{};
    for (const WindowSums<T>& b : blocks_) {
      total.u_sq += b.u_sq;
      total.x_sq += b.x_sq;
      total.stuck += b.stuck;
      total.residual_sq += b.residual_sq;
      total.samples += b.samples;
      total.steps += b.steps;
      total.measured += b.measured;
      total.stick_events += b.stick_events;
      total.slip_events += b.slip_events;
    }
    window_ = total;
    return true;
  }
  // The completed blocks' totals (the window once full(), less before).
  const WindowSums<T>& sums() const noexcept { return window_; }
  bool full() const noexcept { return filled_ == kBlocks; }
  std::uint32_t samples_per_block() const noexcept { return samples_per_block_; }

 private:
  WindowSums<T> blocks_[kBlocks]{};
  WindowSums<T> current_{}, window_{};
  std::uint32_t samples_per_block_ = 1;
  std::size_t next_ = 0;
  std::uint32_t filled_ = 0;
};

// Exponentially weighted mean squares and stuck share: m += g (value - m), g = 1 - exp(-dt/tau).
template <typename T>
class ExponentialWindow {
 public:
  void configure(T gain) noexcept {
    gain_ = gain;
    reset();
  }
  void reset() noexcept { u_sq_ = x_sq_ = stuck_ = residual_sq_ = T(0); }
  void add(T a_u, T a_x, T stuck_fraction, T residual) noexcept {
    u_sq_ += gain_ * (a_u * a_u - u_sq_);
    x_sq_ += gain_ * (a_x * a_x - x_sq_);
    stuck_ += gain_ * (stuck_fraction - stuck_);
    residual_sq_ += gain_ * (residual * residual - residual_sq_);
  }
  T mean_u_sq() const noexcept { return u_sq_; }
  T mean_x_sq() const noexcept { return x_sq_; }
  T stuck_share() const noexcept { return stuck_; }
  T mean_residual_sq() const noexcept { return residual_sq_; }

 private:
  T gain_{}, u_sq_{}, x_sq_{}, stuck_{}, residual_sq_{};
};

}  // namespace stickslip
