// The Cortex-M0+ node's statistics window over its own words (lib/can/word_window.hpp) against
// the same figures computed in long double from every sample it was given (the last ten blocks'
// sums, T_ax, p and K) and rounded to the SeatStats/SeatScene words; and its integer division
// and square root against exact integer arithmetic.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/node_seats.hpp"
#include "stickslip/can/word_window.hpp"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/metrics/den_hartog.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

namespace {

constexpr std::size_t kBlocks = 10;
// The exact quotients of the division test (GCC and Clang on 64-bit hosts).
__extension__ typedef unsigned __int128 Wide;
using Window = can::WordWindow<kBlocks>;
constexpr double kFfk = 45.0, kMass = 88.4;

struct Sample {
  std::int16_t u, x;
  std::uint32_t stuck;  // Q.24
};

// The figures of the window that ends with sample `end` (exclusive), in double: the last (up to)
// ten whole blocks of `per_block` samples.
struct Oracle {
  long double transmissibility, stick_probability, k;
};
Oracle oracle(const std::vector<Sample>& samples, std::size_t end, std::size_t per_block) {
  const std::size_t blocks = end / per_block < kBlocks ? end / per_block : kBlocks;
  long double u = 0.0L, x = 0.0L, stuck = 0.0L;
  const std::size_t begin = end - blocks * per_block;
  for (std::size_t n = begin; n < end; ++n) {
    u += static_cast<long double>(samples[n].u) * samples[n].u;
    x += static_cast<long double>(samples[n].x) * samples[n].x;
    stuck += samples[n].stuck;
  }
  const long double count = end - begin;
  const long double unit_k = static_cast<long double>(den_hartog_factor(kFfk, kMass, 1.0));
  return {std::sqrt(x / u), stuck / count / 16777216.0L, unit_k / (std::sqrt(u / count) / 1024.0L)};
}

// The window's word is the oracle's value rounded to nearest, halves up: exactly, wherever the
// value is further than `margin` words from a half (the oracle's own rounding, and for K the
// 32-bit K(1 m/s^2)^2, below that), and one of the two nearest codes within it.
void check_word(const can::SignalSpec& signal, std::uint16_t word, long double value,
                long double margin, int& near_halves) {
  const long double scaled = std::ldexp(value, signal.fraction_bits);
  const long double below_half = scaled - std::floor(scaled) - 0.5L;
  if (std::fabs(below_half) > margin) {
    LONGS_EQUAL(static_cast<long>(std::floor(scaled + 0.5L)), word);
  } else {
    ++near_halves;
    CHECK(word == static_cast<long>(std::floor(scaled)) ||
          word == static_cast<long>(std::floor(scaled)) + 1);
  }
}

}  // namespace

TEST_GROUP(WordWindow){};

TEST(WordWindow, PublishesTheLastTenBlocksFiguresRoundedToTheirWordsKStagesAfterEachBlock) {
  const std::size_t per_block = 37, total = per_block * 25 + 11;  // the window wraps
  std::mt19937_64 random(20261128);
  std::vector<Sample> samples(total);
  std::normal_distribution<double> floor(0.0, 900.0);  // about 0.9 m/s^2 RMS in words
  std::uniform_int_distribution<std::uint32_t> fraction(0, 1u << 24);
  for (std::size_t n = 0; n < total; ++n) {
    Sample& s = samples[n];
    s.u = static_cast<std::int16_t>(std::lround(floor(random)));
    // The seat's a_x: some of the floor's, some of its own.
    s.x = static_cast<std::int16_t>(std::lround(0.6 * s.u + 0.5 * floor(random)));
    // Stuck for whole steps, slipping, or part of a step.
    const int kind = static_cast<int>(n % 7);
    s.stuck = kind < 3 ? (1u << 24) : kind < 5 ? 0u : fraction(random);
  }
  // The extremes of the words too.
  samples[5] = {-32768, 32767, 1u << 24};
  samples[6] = {32767, -32768, 0};

  Window window;
  window.configure(per_block, kFfk, kMass);
  int published = 0, near_halves = 0;
  for (std::size_t n = 0; n < total; ++n) {
    const can::StatsWords before = window.words();
    window.add(samples[n].u, samples[n].x, samples[n].stuck);
    const can::StatsWords& after = window.words();
    // Sample n (counted from 1: n + 1 samples given) publishes the window of the block that
    // completed kStages samples before it.
    const std::size_t given = n + 1;
    const bool due = given > Window::kStages && (given - Window::kStages) % per_block == 0;
    const bool changed = before.transmissibility.word != after.transmissibility.word ||
                         before.stick_probability.word != after.stick_probability.word ||
                         before.den_hartog_k.word != after.den_hartog_k.word;
    if (!due) {
      CHECK_FALSE(changed);  // a window's words change only when one is published
      if (published == 0) {
        CHECK(can::not_available(can::kSeatStats.signals[0], after.transmissibility.word));
        CHECK(can::not_available(can::kSeatStats.signals[1], after.stick_probability.word));
        CHECK(can::not_available(can::kSeatScene.signals[0], after.den_hartog_k.word));
      }
      continue;
    }
    ++published;
    const Oracle o = oracle(samples, given - Window::kStages, per_block);
    check_word(can::kSeatStats.signals[0], after.transmissibility.word, o.transmissibility, 1e-12L,
               near_halves);
    check_word(can::kSeatStats.signals[1], after.stick_probability.word, o.stick_probability,
               1e-12L, near_halves);
    check_word(can::kSeatScene.signals[0], after.den_hartog_k.word, o.k, 1e-6L, near_halves);
    CHECK_FALSE(after.transmissibility.saturated || after.stick_probability.saturated ||
                after.den_hartog_k.saturated);
  }
  LONGS_EQUAL(25, published);
  CHECK(near_halves <= 2);  // the exact comparison covers (almost) every word
}

TEST(WordWindow, WordsChangeOnlyWhenAWindowIsPublished) {
  const std::size_t per_block = 20;
  Window window;
  window.configure(per_block, kFfk, kMass);
  std::mt19937_64 random(7);
  std::uniform_int_distribution<int> word(-3000, 3000);
  int changes = 0;
  for (std::size_t n = 1; n <= per_block * 15; ++n) {
    const can::StatsWords before = window.words();
    window.add(static_cast<std::int16_t>(word(random)), static_cast<std::int16_t>(word(random)),
               n % 2 == 0 ? 1u << 24 : 0u);
    const bool changed = before.transmissibility.word != window.words().transmissibility.word ||
                         before.stick_probability.word != window.words().stick_probability.word ||
                         before.den_hartog_k.word != window.words().den_hartog_k.word;
    if (changed) {
      ++changes;
      CHECK(n > Window::kStages && (n - Window::kStages) % per_block == 0);
    }
  }
  CHECK(changes >= 14);  // every window's T_ax moves on random words
}

TEST(WordWindow, BlocksShorterThanItsStagesPublishTheNewestWindowEveryKStagesSamples) {
  // Two samples per block: blocks complete while the stages run (one stage per sample at most),
  // and each publication is of the newest window when its stages began, which is when the one
  // before was published: published at samples 7, 12, 17, ... (kStages = 5), the windows of the
  // blocks completed by sample 2, then by the sample before the previous publication (6, 10,
  // 16, ...).
  const std::size_t per_block = 2;
  Window window;
  window.configure(per_block, kFfk, kMass);
  std::vector<Sample> samples;
  std::mt19937_64 random(3);
  std::uniform_int_distribution<int> word(-2000, 2000);
  int published = 0, near_halves = 0;
  std::size_t window_end = per_block;
  for (std::size_t given = 1; given <= 40; ++given) {
    samples.push_back({static_cast<std::int16_t>(word(random)),
                       static_cast<std::int16_t>(word(random)), given % 3 == 0 ? 1u << 24 : 0u});
    const std::uint16_t before = window.words().transmissibility.word;
    window.add(samples.back().u, samples.back().x, samples.back().stuck);
    // The first block completes at sample per_block; its stages end kStages samples later, and
    // each publication starts the stages of the newest block at once.
    const std::size_t first = per_block + Window::kStages;
    const bool due = given >= first && (given - first) % Window::kStages == 0;
    if (!due) {
      LONGS_EQUAL(before, window.words().transmissibility.word);
      continue;
    }
    ++published;
    const Oracle o = oracle(samples, window_end, per_block);
    window_end = (given - 1) / per_block * per_block;
    check_word(can::kSeatStats.signals[0], window.words().transmissibility.word, o.transmissibility,
               1e-12L, near_halves);
    check_word(can::kSeatStats.signals[1], window.words().stick_probability.word,
               o.stick_probability, 1e-12L, near_halves);
  }
  LONGS_EQUAL((40 - (per_block + Window::kStages)) / Window::kStages + 1, published);
  CHECK(published >= 5);
  CHECK(near_halves == 0);
}

TEST(WordWindow, SilentFloorGivesZeroTransmissibilityAndKNotAvailable) {
  // As the observer: T_ax = 0 without input, K infinite with friction (not available).
  Window window;
  window.configure(10, kFfk, kMass);
  for (int n = 0; n < 10 + int(Window::kStages); ++n) window.add(0, 0, 1u << 24);
  LONGS_EQUAL(0, window.words().transmissibility.word);
  LONGS_EQUAL(32768, window.words().stick_probability.word);
  CHECK(can::not_available(can::kSeatScene.signals[0], window.words().den_hartog_k.word));
}

TEST(WordWindow, BitLengthCountsTheSignificantBitsAtEveryWidth) {
  using can::word_window_detail::bit_length;
  LONGS_EQUAL(0, bit_length(0u));
  std::mt19937_64 random(5);
  for (int bits = 1; bits <= 64; ++bits) {
    const std::uint64_t top = std::uint64_t{1} << (bits - 1);
    const std::uint64_t all = bits == 64 ? ~std::uint64_t{0} : (top << 1) - 1u;
    LONGS_EQUAL(bits, bit_length(top));
    LONGS_EQUAL(bits, bit_length(all));
    for (int n = 0; n < 100; ++n) LONGS_EQUAL(bits, bit_length(top | (random() & (top - 1u))));
  }
}

TEST(WordWindow, DivisionGivesTheExactScaledQuotientOrTheCap) {
  // divide_scaled(a, b, f, cap) = floor(a 2^f / b), capped, against Wide.
  using can::word_window_detail::divide_scaled;
  std::mt19937_64 random(11);
  const std::uint64_t cap = std::uint64_t{1} << 40;
  long compared = 0, capped = 0, mismatched = 0;
  for (int n = 0; n < 300000; ++n) {
    const std::uint64_t a = random() >> (random() % 64);
    const std::uint64_t b = (random() >> (1 + random() % 63)) | 1u;  // 0 < b < 2^63
    const int f = static_cast<int>(random() % 60);
    const Wide exact = (static_cast<Wide>(a) << f) / b;
    const std::uint64_t expected = exact >= cap ? cap : static_cast<std::uint64_t>(exact);
    if (divide_scaled(a, b, f, cap) != expected) ++mismatched;
    ++compared;
    capped += exact >= cap ? 1 : 0;
  }
  // The edges: quotients just below and at the cap, a = b, a = 0, b = 2^63 - 1.
  for (const std::uint64_t b : {std::uint64_t{1}, std::uint64_t{3}, (std::uint64_t{1} << 63) - 1}) {
    for (const int f : {0, 1, 26, 40}) {
      for (const std::uint64_t a : {std::uint64_t{0}, b, b - 1, b + 1, ~std::uint64_t{0}}) {
        const Wide exact = (static_cast<Wide>(a) << f) / b;
        const std::uint64_t expected = exact >= cap ? cap : static_cast<std::uint64_t>(exact);
        if (divide_scaled(a, b, f, cap) != expected) ++mismatched;
        ++compared;
      }
    }
  }
  LONGS_EQUAL(0, mismatched);
  CHECK(capped > 1000 && capped < compared - 1000);
}

TEST(WordWindow, DivisionRunsAtMostItsStatedRoundsAndTheWorstQuotientReachesThem) {
  // The loop bound kMaxQuotientBits + 1 (port/baremetal/loop-bounds.json): never exceeded over
  // random operands, and reached where k + f = kMaxQuotientBits (the largest quotient formed bit
  // by bit rather than capped at once).
  using can::word_window_detail::divide_scaled;
  using can::word_window_detail::kMaxQuotientBits;
  const std::uint64_t cap = std::uint64_t{1} << 40;
  std::mt19937_64 random(17);
  int most = 0;
  for (int n = 0; n < 300000; ++n) {
    const std::uint64_t a = random() >> (random() % 64);
    const std::uint64_t b = (random() >> (1 + random() % 63)) | 1u;
    int rounds = 0;
    divide_scaled(a, b, static_cast<int>(random() % 80), cap, &rounds);
    if (rounds > most) most = rounds;
  }
  CHECK(most <= kMaxQuotientBits + 1);
  // k = bit_length(a) - bit_length(b) = 20 and f = 20: k + f - 1 < kMaxQuotientBits, 41 rounds,
  // and the quotient (about 2^40.99) is still formed bit by bit before it is capped.
  int rounds = 0;
  const std::uint64_t a = (std::uint64_t{1} << 40) - 1, b = (std::uint64_t{1} << 20) - 1;
  divide_scaled(a, b, kMaxQuotientBits - 20, cap, &rounds);
  LONGS_EQUAL(kMaxQuotientBits + 1, rounds);
}

TEST(WordWindow, SquareRootIsTheExactFloorBelow2To36) {
  using can::word_window_detail::square_root;
  std::mt19937_64 random(13);
  long mismatched = 0;
  const auto check = [&](std::uint64_t v) {
    const std::uint64_t r = square_root(v);
    if (!(r * r <= v && (r + 1) * (r + 1) > v)) ++mismatched;
  };
  for (int n = 0; n < 200000; ++n) check(random() >> (28 + random() % 36));  // below 2^36
  for (std::uint64_t r = 0; r < (std::uint64_t{1} << 18); r += 97) {
    check(r * r);
    if (r > 0) check(r * r - 1);
  }
  check((std::uint64_t{1} << 36) - 1);
  LONGS_EQUAL(0, mismatched);
}

TEST(WordWindow, ScaledSeatRefusesASampleRateWhoseWindowWouldNotFitItsCounters) {
  // A window below 2^32 samples keeps every sum exact in 64 bits; a seat of 1 mg on 1 GN/m fits
  // Q7.24's scene units at dt = 3 ns (3.3e9 samples in 10 s) but not at 2 ns (5e9).
  OscillatorParams p;
  p.model = FrictionModel::linear;
  p.mass_kg = 1e-6;
  p.stiffness_n_per_m = 1e9;
  p.damping_ns_per_m = 0.0;
  p.kinetic_friction_n = p.static_friction_n = 0.0;
  p.integrator = Integrator::exact;
  p.input_range_m_per_s2 = 32.768;
  p.displacement_range_m = 1e-6;
  p.dt_s = 3e-9;
  can::ScaledSeat<Fixed32, NoFriction> seat;
  CHECK_TRUE(seat.configure(p).ok());
  p.dt_s = 2e-9;
  const ConfigResult refused = seat.configure(p);
  CHECK(refused.status == Status::out_of_range);
  STRCMP_CONTAINS("dt_s: the statistics window (10 s) would hold over 4e9 samples",
                  refused.message.c_str());
}
