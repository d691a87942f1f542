// The oracle of the soak: every statistic the observer and the running statistics publish,
// recomputed from the same samples in long double, with the bounds the comparisons use.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "stickslip/metrics/iso2631_weighting.hpp"

namespace stickslip::soak {

constexpr std::uint64_t kRecomputeBlock = 1000000;

// The whole-stream recomputation: squares and stuck fractions summed in long double, in blocks
// of 1e6 samples (a plain long double sum over 1e9 terms would itself lose ~1e-10).
struct WholeStreamReference {
  long double total_u = 0, total_x = 0, total_stuck = 0;
  long double block_u = 0, block_x = 0, block_stuck = 0;
  std::uint64_t in_block = 0;

  void add(long double u_sq, long double x_sq, long double stuck) {
    block_u += u_sq;
    block_x += x_sq;
    block_stuck += stuck;
    if (++in_block == kRecomputeBlock) {
      total_u += block_u;
      total_x += block_x;
      total_stuck += block_stuck;
      block_u = block_x = block_stuck = 0;
      in_block = 0;
    }
  }
  double rms_ratio() const {
    return static_cast<double>(std::sqrt((total_x + block_x) / (total_u + block_u)));
  }
  double stuck_share(std::uint64_t steps) const {
    return static_cast<double>((total_stuck + block_stuck) / static_cast<long double>(steps));
  }
};

// m <- m + g (v - m) in long double, with a running first-order bound of how far the same
// recurrence evaluated in T (unit roundoff u) can be from it: each step rounds v (a square),
// v - m, the product and the sum, and the recurrence forgets old errors at the rate 1 - g.
struct ExponentialReference {
  long double mean = 0;
  double bound = 0;      // on |m_T - m|, first order in u
  double max_mean = 0;   // for MTVV: the largest m so far ...
  double max_bound = 0;  // ... and the largest bound so far (|max m_T - max m| <= max bound)

  void add(long double value, long double gain, double u) {
    const double previous = static_cast<double>(mean);
    mean += gain * (value - mean);
    const double g = static_cast<double>(gain), v = std::fabs(static_cast<double>(value));
    bound = (1.0 - g) * bound + u * (std::fabs(static_cast<double>(mean)) + 3.0 * g * v +
                                     2.0 * g * std::fabs(previous));
    max_mean = std::fmax(max_mean, static_cast<double>(mean));
    max_bound = std::fmax(max_bound, bound);
  }
};

// One block of the window recomputation.
struct ReferenceBlock {
  long double u_sq = 0, x_sq = 0, stuck = 0;
  std::uint32_t samples = 0, stick_events = 0, slip_events = 0;
};

// The observer's window mirrored: the same number of blocks, each summed in long double.
template <std::size_t Blocks>
struct WindowReference {
  ReferenceBlock blocks[Blocks], current;
  std::size_t next_block = 0;
  std::uint64_t blocks_done = 0;

  void add(long double u_sq, long double x_sq, long double stuck, bool stick_event,
           bool slip_event) {
    current.u_sq += u_sq;
    current.x_sq += x_sq;
    current.stuck += stuck;
    current.stick_events += stick_event ? 1u : 0u;
    current.slip_events += slip_event ? 1u : 0u;
    ++current.samples;
  }
  // Closes the current block into the ring; the sums over the window's blocks.
  ReferenceBlock complete_block() {
    blocks[next_block] = current;
    next_block = next_block + 1 == Blocks ? 0 : next_block + 1;
    ++blocks_done;
    current = ReferenceBlock{};
    ReferenceBlock w;
    for (const ReferenceBlock& b : blocks) {
      w.u_sq += b.u_sq;
      w.x_sq += b.x_sq;
      w.stuck += b.stuck;
      w.samples += b.samples;
      w.stick_events += b.stick_events;
      w.slip_events += b.slip_events;
    }
    return w;
  }
};

// Ride comfort recomputed: the weighted samples from a second pair of weighting filters on the
// same input (identical by construction, so the peak must match to the bit), their squares and
// fourth powers summed blockwise in long double, and the seat's 1 s running mean square (MTVV).
template <typename T>
struct ComfortReference {
  WeightingFilter<T> floor_filter, seat_filter;
  WholeStreamReference floor_sq, seat_sq;  // (only the u channel of each is used for squares)
  WholeStreamReference fourth;             // u channel: floor^4, x channel: seat^4
  ExponentialReference running_ms;         // the seat's 1 s running mean square (MTVV)
  T seat_peak = T(0);
  double comfort_dt = 0;  // RideComfort keeps 1 / its sample rate
  long double running_gain = 0;
  double u = 0;  // unit roundoff of T

  // Configured as RideComfort configures its own.
  void configure(ComfortWeighting weighting, double dt, double unit_roundoff) {
    floor_filter.configure(weighting, 1.0 / dt);
    seat_filter.configure(weighting, 1.0 / dt);
    comfort_dt = 1.0 / (1.0 / dt);
    running_gain = static_cast<long double>(static_cast<T>(-std::expm1(-comfort_dt / 1.0)));
    u = unit_roundoff;
  }
  void add(T a_floor, T a_seat) {
    const auto f = static_cast<long double>(floor_filter.step(a_floor));
    const auto s = static_cast<long double>(seat_filter.step(a_seat));
    const T s_t = static_cast<T>(s);
    seat_peak = std::fabs(s_t) > seat_peak ? std::fabs(s_t) : seat_peak;
    floor_sq.add(f * f, 0, 0);
    seat_sq.add(s * s, 0, 0);
    fourth.add(f * f * f * f, s * s * s * s, 0);
    running_ms.add(s * s, running_gain, u);
  }
  // After `total` samples (the reset sample included).
  double floor_weighted_rms(long double total) const {
    return static_cast<double>(std::sqrt((floor_sq.total_u + floor_sq.block_u) / total));
  }
  double seat_weighted_rms(long double total) const {
    return static_cast<double>(std::sqrt((seat_sq.total_u + seat_sq.block_u) / total));
  }
  double floor_vdv() const {
    return static_cast<double>(std::sqrt(
        std::sqrt((fourth.total_u + fourth.block_u) * static_cast<long double>(comfort_dt))));
  }
  double seat_vdv() const {
    return static_cast<double>(std::sqrt(
        std::sqrt((fourth.total_x + fourth.block_x) * static_cast<long double>(comfort_dt))));
  }
};

}  // namespace stickslip::soak
