// The root search of the exact integrator's event location (falling_root(),
// integrators/taylor_segment.hpp): its trip count is a bound, kMaxRootIterations<T>, and within
// it the root is found to the search's tolerance 4 eps (lo + hi), whatever Newton does.
//
// f(u) = r - u, whose computed sign changes exactly at r (a correctly rounded difference is zero
// only where its operands are equal), so the tolerance is checked against the root itself. The
// values at the ends and the slope handed to the search are not f's (the search uses the ends'
// values only for its first iterate, the secant, which would land on a line's root at once): the
// first iterate is the bracket's midpoint, a positive slope makes every iteration bisect, and one
// eight times too steep makes Newton creep toward the root by an eighth of the way per step,
// never finishing, so that the search reaches its last bisection. Brackets run over [0, 1] and
// its parts down to a root near the bracket's start, at roots spread over 2^-20 .. 1.
#include <cmath>
#include <cstdint>
#include <limits>

#include "CppUTest/TestHarness.h"
#include "stickslip/integrators/taylor_segment.hpp"

using namespace stickslip;

namespace {

struct SearchTally {
  double worst_error_in_tolerances = 0.0;
  int most_iterations = 0;
  long searches = 0;
};

template <typename T>
PaddedPolynomial<T> linear(T constant, T slope) {
  PaddedPolynomial<T> p;
  p.degree = 1;
  p.c[0] = constant;
  p.c[1] = slope;
  return p;
}

template <typename T>
PaddedPolynomial<T> constant(T value) {
  PaddedPolynomial<T> p;
  p.degree = 0;
  p.c[0] = value;
  return p;
}

// Searches f = r - u over brackets [lo, hi] around r, with the given (false) slope of f.
template <typename T>
SearchTally search_roots(T slope_of_f) {
  SearchTally tally;
  std::uint64_t state = 0x243f6a8885a308d3u;  // SplitMix64: the same roots on every machine
  auto uniform = [&state]() {
    state += 0x9e3779b97f4a7c15u;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) / 9007199254740992.0;  // [0, 1)
  };
  const PaddedPolynomial<T> slope = constant(slope_of_f);
  for (int n = 0; n < 4000; ++n) {
    const T r =
        static_cast<T>(std::ldexp(0.5 + 0.5 * uniform(), -static_cast<int>(21 * uniform())));
    // The bracket: [0, 1], or from a point below r (or 0) to a point above it (or 1).
    const T lo = n % 3 == 0 ? T(0) : static_cast<T>(static_cast<double>(r) * uniform());
    const T hi = n % 3 == 1 ? T(1) : static_cast<T>(r + (T(1) - r) * static_cast<T>(uniform()));
    if (!(lo < r && r < hi)) continue;
    const PaddedPolynomial<T> f = linear(r, T(-1));
    const FallingRoot<T> found = falling_root<T>(f, slope, nullptr, T(1), lo, hi, T(1), T(-1));
    const double tolerance = 4.0 * static_cast<double>(std::numeric_limits<T>::epsilon()) *
                             (static_cast<double>(lo) + static_cast<double>(hi));
    const double error = std::fabs(static_cast<double>(found.root) - static_cast<double>(r));
    if (error / tolerance > tally.worst_error_in_tolerances)
      tally.worst_error_in_tolerances = error / tolerance;
    if (found.iterations > tally.most_iterations) tally.most_iterations = found.iterations;
    ++tally.searches;
  }
  return tally;
}

}  // namespace

TEST_GROUP(RootSearch){};

TEST(RootSearch, ItsBoundIsNewtonsIterationsPlusTheBisectionsThatReachTheTolerance) {
  LONGS_EQUAL(22, kRootBisections<float>);
  LONGS_EQUAL(51, kRootBisections<double>);
  LONGS_EQUAL(kRootNewtonIterationsFloat + 22, kMaxRootIterations<float>);
  LONGS_EQUAL(kRootNewtonIterationsDouble + 51, kMaxRootIterations<double>);
}

TEST(RootSearch, BisectingEveryIterationMeetsTheToleranceWellWithinTheBound) {
  const SearchTally f = search_roots<float>(1.0f);
  const SearchTally d = search_roots<double>(1.0);
  CHECK(f.searches > 3000 && d.searches > 3000);
  CHECK(f.worst_error_in_tolerances <= 1.0);
  CHECK(d.worst_error_in_tolerances <= 1.0);
  // Bisection alone needs at most kRootBisections + 1 iterations (the last to see the bracket).
  CHECK(f.most_iterations <= kRootBisections<float> + 1);
  CHECK(d.most_iterations <= kRootBisections<double> + 1);
}

TEST(RootSearch, NewtonThatNeverFinishesLeavesTheBisectionsToMeetTheToleranceAtTheBound) {
  const SearchTally f = search_roots<float>(-8.0f);
  const SearchTally d = search_roots<double>(-8.0);
  CHECK(f.searches > 3000 && d.searches > 3000);
  CHECK(f.worst_error_in_tolerances <= 1.0);
  CHECK(d.worst_error_in_tolerances <= 1.0);
  // The bound is reached: the worst of these searches runs every iteration it allows.
  LONGS_EQUAL(kMaxRootIterations<float>, f.most_iterations);
  LONGS_EQUAL(kMaxRootIterations<double>, d.most_iterations);
}
