#include "stickslip/host/signals/random.hpp"

#include <cmath>

#include "stickslip/host/signals/deterministic_math.hpp"

namespace stickslip::host {
namespace {
std::uint64_t rotate_left(std::uint64_t x, int k) noexcept {
  return (x << k) | (x >> (64 - k));
}
}  // namespace

Xoshiro256StarStar::Xoshiro256StarStar(std::uint64_t seed, std::uint64_t stream) noexcept {
  // Distinct streams start splitmix64 at distinct, well-mixed points.
  SplitMix64 mixer(seed ^ SplitMix64(stream).next());
  for (std::uint64_t& word : s_) word = mixer.next();
  // An all-zero state would stay zero forever; splitmix64 makes it practically impossible.
  if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0) s_[0] = 1;
}

std::uint64_t Xoshiro256StarStar::next() noexcept {
  const std::uint64_t result = rotate_left(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotate_left(s_[3], 45);
  return result;
}

double GaussianSource::next() noexcept {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  for (;;) {
    const double u = 2.0 * uniform_.uniform() - 1.0;  // [-1, 1), exact
    const double v = 2.0 * uniform_.uniform() - 1.0;
    const double s = u * u + v * v;
    if (s >= 1.0 || s == 0.0) continue;  // outside the unit disc (or its centre): draw again
    const double factor = std::sqrt(-2.0 * deterministic_log(s) / s);
    spare_ = v * factor;
    has_spare_ = true;
    return u * factor;
  }
}

}  // namespace stickslip::host
