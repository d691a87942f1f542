// Reproducible random numbers: the same seed gives the same sequence on every machine and
// standard library. <random>'s distributions are implementation-defined, so we use our own:
// splitmix64 for seeding, xoshiro256** as the generator, and Marsaglia's polar method for
// Gaussians (its logarithm from deterministic_math, not libm).
#pragma once

#include <cstdint>

namespace stickslip::host {

// Steele, Lea, Flood (2014): a 64-bit counter through a strong mixer; used to expand one seed
// into the 256-bit xoshiro state, as its authors recommend.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) noexcept : state_(seed) {}
  std::uint64_t next() noexcept {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

// Blackman and Vigna's xoshiro256** 1.0. `stream` selects an independent sequence for the same
// seed (each component of a generated signal draws from its own stream).
class Xoshiro256StarStar {
 public:
  explicit Xoshiro256StarStar(std::uint64_t seed, std::uint64_t stream = 0) noexcept;
  // A given 256-bit state (not all zero), e.g. to check the reference sequence.
  static Xoshiro256StarStar from_state(std::uint64_t s0, std::uint64_t s1, std::uint64_t s2,
                                       std::uint64_t s3) noexcept {
    Xoshiro256StarStar generator(0);
    generator.s_[0] = s0;
    generator.s_[1] = s1;
    generator.s_[2] = s2;
    generator.s_[3] = s3;
    return generator;
  }
  std::uint64_t next() noexcept;
  // Uniform on [0, 1) with 53 random bits (exact conversion, no rounding).
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t s_[4];
};

// Standard normal deviates by the Marsaglia polar method (two per accepted pair).
class GaussianSource {
 public:
  explicit GaussianSource(std::uint64_t seed, std::uint64_t stream = 0) noexcept
      : uniform_(seed, stream) {}
  double next() noexcept;

 private:
  Xoshiro256StarStar uniform_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace stickslip::host
