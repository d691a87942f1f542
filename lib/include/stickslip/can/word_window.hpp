// The SeatStats/SeatScene figures (T_ax, p, K) of a node whose seat runs without floating point
// (the Cortex-M0+'s Q7.24 seat, node_seats.hpp's ScaledSeat): the observer's block window
// (observer/window_statistics.hpp: the last kBlocks completed blocks) over the node's own words,
// and its figures straight to their words, all in integers.
//
// The words: a_u is the SeatInput word itself (the seat's input, exactly), a_x the SeatMotion word
// the node sends (both 2^-10 m/s^2 per bit), the stuck fraction the step's in Q.24. Their sums
// are exact (uint64: a squared word < 2^30, a window < 2^32 samples), and each figure's word is
// the exact sum's figure rounded to nearest (half up), as quantise() rounds: T_ax =
// sqrt(sum a_x^2 / sum a_u^2) and p = sum stuck / samples exactly; K = K(1 m/s^2) / RMS(a_u) with
// K(1 m/s^2)^2 held to 32 significant bits. They differ from the observer's figures on unrounded
// values only by a_x's rounding to its word, below T_ax's own word (2^-12) for any a_x RMS above a
// few words.
//
// Per sample: two 16 x 16-bit squares and three 64-bit adds; when a block completes, the window's
// sums gain it and lose the oldest (exact). The next kStages samples each run one stage: T_ax's
// division, its square root, p's division, K's division, its square root; then the three words
// are published together (a SeatStats frame never mixes two windows). A stage is one long
// division of at most kMaxQuotientBits + 1 quotient bits or one square root of kRootBits bits,
// shift-and-subtract in 64-bit words (up to about 900 ARMv6-M instructions, docs/EMBEDDED.md):
// all of them in one sample would land about 3,900 on one frame, a division and its root
// together about 1,700. No software float, so every loop has the trip count stated here
// (port/baremetal/loop-bounds.json).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/ecu_node.hpp"
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip::can {

namespace word_window_detail {

// A quotient needs at most this many bits: a figure's word is below 2^16, and the division gives
// 4 (2^F figure)^2 < 2^34 (or 2 p 2^15 <= 2^16); anything from 2^40 on saturates.
inline constexpr int kMaxQuotientBits = 40;
// Square roots are taken of values below 2^36: roots below 2^18, one bit per round.
inline constexpr int kRootBits = 18;

// The number of significant bits of v (0 for 0), from the leading zeros of its upper or lower
// half: no loop, and no 64-bit shift by a variable amount (a libgcc call on ARMv6-M, whose
// __clzsi2 is loop-free).
inline int bit_length(std::uint64_t v) noexcept {
  const auto high = static_cast<std::uint32_t>(v >> 32);
  const auto low = static_cast<std::uint32_t>(v);
  if (high != 0u) return 64 - __builtin_clz(high);
  return low != 0u ? 32 - __builtin_clz(low) : 0;
}

// floor(a 2^f / b), or `cap` where that is >= cap, for 0 < b < 2^63, f >= 0 and cap <= 2^40:
// restoring division, one quotient bit per round from the quotient's top, at most
// kMaxQuotientBits + 1 rounds (a quotient that would need more is above cap before any is formed).
// `rounds_run`, where given, receives the rounds the loop runs (for the test of its bound).
inline std::uint64_t divide_scaled(std::uint64_t a, std::uint64_t b, int f, std::uint64_t cap,
                                   int* rounds_run = nullptr) noexcept {
  if (a == 0u) return 0u;
  // 2^(k-1) < a / b < 2^(k+1): the quotient is above 2^(k+f-1) and has at most k + 1 + f bits.
  const int k = bit_length(a) - bit_length(b);
  if (k + f - 1 >= kMaxQuotientBits) return cap;
  // The remainder r < b starts with a's bits above its lowest k + 1 (below b: a < b 2^k), which
  // `rest` feeds in from its top, then the zeros of 2^f; with k < 0 (a < b / 2) the first -k - 1
  // quotient bits are zero and are skipped: r 2^(-k-1) < b still.
  std::uint64_t r = 0, rest = 0;
  int rounds = 0;
  if (k >= 0) {
    r = k + 1 < 64 ? a >> (k + 1) : 0u;
    rest = a << (63 - k);
    rounds = k + 1 + f;
  } else {
    const int zeros = -k - 1 < f ? -k - 1 : f;
    r = a << zeros;
    rounds = f - zeros;
  }
  if (rounds_run != nullptr) *rounds_run = rounds;
  std::uint64_t q = 0;
  for (int round = 0; round < rounds; ++round) {
    r = (r << 1) | (rest >> 63);  // r < b < 2^63: no bit lost
    rest <<= 1;
    q <<= 1;
    if (r >= b) {
      r -= b;
      q |= 1u;
    }
  }
  return q >= cap ? cap : q;
}

// floor(sqrt(v)) for v < 2^(2 kRootBits), kRootBits rounds.
inline std::uint32_t square_root(std::uint64_t v) noexcept {
  std::uint64_t root = 0, bit = std::uint64_t{1} << (2 * kRootBits - 2);
  for (int round = 0; round < kRootBits; ++round) {
    if (v >= root + bit) {
      v -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<std::uint32_t>(root);
}

// The word of a figure x >= 0 given y = floor(4 (2^F x)^2) (F the signal's fraction bits):
// round(2^F x) = floor((floor(2 * 2^F x) + 1) / 2), and floor(2 * 2^F x) = floor(sqrt(y)).
// y at kSaturatedQuarter or above is a code of 65534.5 or more: saturated.
inline constexpr std::uint64_t kSaturatedQuarter =
    std::uint64_t{2 * kUnsignedMax + 1} * (2 * kUnsignedMax + 1);
inline Quantised word_of_quarter(std::uint64_t y) noexcept {
  if (y >= kSaturatedQuarter) return {kUnsignedMax, true};
  return {static_cast<std::uint16_t>((square_root(y) + 1u) / 2u), false};
}

}  // namespace word_window_detail

template <std::size_t kBlocks>
class WordWindow {
  static_assert(kBlocks >= 2, "a block window needs at least two blocks");

 public:
  // Samples after a completed block until its figures are published.
  static constexpr unsigned kStages = 5;

  // samples_per_block (at least 1; the window is kBlocks of them, below 2^32 samples), and F_fk
  // and m for K (as the seat's configure() has accepted them). With fewer than kStages + 1
  // samples per block a window is published every kStages samples, kStages samples late.
  void configure(std::uint32_t samples_per_block, double kinetic_friction_n,
                 double mass_kg) noexcept {
    samples_per_block_ = samples_per_block < 1 ? 1 : samples_per_block;
    // K(1 m/s^2)^2 = mantissa 2^exponent, the mantissa in [2^31, 2^32) (0 without friction).
    const double unit_k = den_hartog_factor(kinetic_friction_n, mass_kg, 1.0);
    int exponent = 0;
    const double fraction = std::frexp(unit_k * unit_k, &exponent);  // [0.5, 1)
    double mantissa = std::round(std::ldexp(fraction, 32));
    if (mantissa >= 4294967296.0) {
      mantissa = 2147483648.0;
      ++exponent;
    }
    unit_k_squared_mantissa_ = static_cast<std::uint32_t>(mantissa);
    unit_k_squared_exponent_ = exponent - 32;
    reset();
  }

  void reset() noexcept {
    clear(current_);
    clear(window_);
    clear(figured_);
    newer_block_ = false;
    next_ = 0;
    filled_ = 0;  // the blocks are stale until written again
    stage_ = 0;
    not_available(words_);
    not_available(pending_);
  }

  // One sample: its a_u and a_x words (two's complement) and the step's stuck fraction in Q.24
  // (0 .. 2^24).
  void add(std::int16_t a_u_word, std::int16_t a_x_word,
           std::uint32_t stuck_fraction_q24) noexcept {
    if (stage_ != 0) run_stage();  // one stage per sample at most
    const std::int32_t u = a_u_word, x = a_x_word;
    current_.u_sq += static_cast<std::uint32_t>(u * u);
    current_.x_sq += static_cast<std::uint32_t>(x * x);
    current_.stuck += stuck_fraction_q24;
    if (++current_.samples < samples_per_block_) return;
    // The window gains this block and loses the one it replaces (none until the window is
    // full): integer sums, exact, so nothing drifts however long the run.
    Sums& oldest = blocks_[next_];
    window_.u_sq += current_.u_sq;
    window_.x_sq += current_.x_sq;
    window_.stuck += current_.stuck;
    window_.samples += current_.samples;
    if (filled_ == kBlocks) {
      window_.u_sq -= oldest.u_sq;
      window_.x_sq -= oldest.x_sq;
      window_.stuck -= oldest.stuck;
      window_.samples -= oldest.samples;
    } else {
      ++filled_;
    }
    oldest = current_;
    next_ = next_ + 1 == kBlocks ? 0 : next_ + 1;
    clear(current_);
    // The stages figure this window from the next sample on; blocks shorter than the stages
    // (below kStages + 1 samples) complete while they run, and the newest is figured next.
    if (stage_ == 0) {
      start_stages();
    } else {
      newer_block_ = true;
    }
  }

  // As of the last published window; not available before the first block's figures.
  const StatsWords& words() const noexcept { return words_; }

 private:
  struct Sums {
    std::uint64_t u_sq = 0, x_sq = 0, stuck = 0;  // words^2; Q.24
    std::uint32_t samples = 0;
  };
  // Member by member: a whole-struct store is a memset or memcpy call whose length the
  // worst-case analysis (tools/elf-wcet.py) may not see set in the calling block.
  static void clear(Sums& sums) noexcept {
    sums.u_sq = sums.x_sq = sums.stuck = 0;
    sums.samples = 0;
  }
  static void not_available(Quantised& q) noexcept {
    q.word = kUnsignedNotAvailable;
    q.saturated = false;
  }
  static void not_available(StatsWords& words) noexcept {
    not_available(words.transmissibility);
    not_available(words.stick_probability);
    not_available(words.den_hartog_k);
  }

  // An if chain, not a switch: five cases compile to a jump table on the Cortex-M0+, which the
  // firmware's static bound (tools/elf-wcet.py) cannot follow.
  void run_stage() noexcept {
    using namespace word_window_detail;
    if (stage_ == 1) {
      // 4 (2^F T_ax)^2 = sum a_x^2 2^(2F + 2) / sum a_u^2 (the words share their scale); T_ax =
      // 0 without input, as the observer's (the word of quarter 0 is 0).
      static_assert(kSeatInput.signals[0].fraction_bits == kSeatMotion.signals[0].fraction_bits,
                    "a_u and a_x words of one scale");
      const int f = kSeatStats.signals[0].fraction_bits;
      quarter_ = figured_.u_sq == 0u
                     ? 0u
                     : divide_scaled(figured_.x_sq, figured_.u_sq, 2 * f + 2, kSaturatedQuarter);
    } else if (stage_ == 2) {
      pending_.transmissibility = word_of_quarter(quarter_);
    } else if (stage_ == 3) {
      // floor(2 2^F p) = floor(sum stuck / (samples 2^(24 - F - 1))), p <= 1: at most 2^(F+1).
      constexpr int f = kSeatStats.signals[1].fraction_bits;
      static_assert(f + 1 <= 24 && f < 16, "p's word from the Q.24 stuck sum");
      const std::uint64_t twice = divide_scaled(
          figured_.stuck, std::uint64_t{figured_.samples} << (24 - f - 1), 0, kSaturatedQuarter);
      pending_.stick_probability = {static_cast<std::uint16_t>((twice + 1u) / 2u), false};
    } else if (stage_ == 4) {
      quarter_ = den_hartog_k_quarter();
    } else {
      pending_.den_hartog_k = den_hartog_k_word(quarter_);
      words_ = pending_;
    }
    if (stage_ != kStages) {
      ++stage_;
    } else if (newer_block_) {
      start_stages();
    } else {
      stage_ = 0;
    }
  }

  // The window the stages figure, as it stands now.
  void start_stages() noexcept {
    figured_.u_sq = window_.u_sq;
    figured_.x_sq = window_.x_sq;
    figured_.stuck = window_.stuck;
    figured_.samples = window_.samples;
    newer_block_ = false;
    stage_ = 1;
  }

  // K = K(1 m/s^2) / RMS(a_u), RMS(a_u)^2 = sum a_u^2 / (samples 2^(2 Fu)) (Fu: a_u's fraction
  // bits): 4 (2^Fk K)^2 = mantissa samples 2^(exponent + 2 Fk + 2 Fu + 2) / sum a_u^2; 0 where
  // den_hartog_k_word() has K without it.
  std::uint64_t den_hartog_k_quarter() const noexcept {
    using namespace word_window_detail;
    if (unit_k_squared_mantissa_ == 0u || figured_.u_sq == 0u) return 0u;
    const int shift = unit_k_squared_exponent_ + 2 * kSeatScene.signals[0].fraction_bits +
                      2 * kSeatInput.signals[0].fraction_bits + 2;
    std::uint64_t numerator =
        fixed_point_detail::multiply_32x32(unit_k_squared_mantissa_, figured_.samples);
    if (shift < 0) numerator = -shift < 64 ? numerator >> -shift : 0u;  // floor of a floor
    return divide_scaled(numerator, figured_.u_sq, shift > 0 ? shift : 0, kSaturatedQuarter);
  }
  // K's word from that quarter. As den_hartog_factor(): 0 without friction, infinite (not
  // available) without input.
  Quantised den_hartog_k_word(std::uint64_t quarter) const noexcept {
    if (unit_k_squared_mantissa_ == 0u) return {0, false};
    if (figured_.u_sq == 0u) return {kUnsignedNotAvailable, false};
    return word_window_detail::word_of_quarter(quarter);
  }

  Sums blocks_[kBlocks]{};
  Sums current_{}, window_{};
  Sums figured_{};  // the window as the running stages figure it
  std::uint32_t samples_per_block_ = 1;
  std::size_t next_ = 0;
  std::size_t filled_ = 0;     // blocks written since reset(), up to kBlocks
  unsigned stage_ = 0;         // 0: idle; else the stage the next sample runs
  std::uint64_t quarter_ = 0;  // a division's result for the next stage's square root
  bool newer_block_ = false;   // a block completed while the stages ran
  std::uint32_t unit_k_squared_mantissa_ = 0;
  int unit_k_squared_exponent_ = 0;
  StatsWords pending_{}, words_{};
};

}  // namespace stickslip::can
