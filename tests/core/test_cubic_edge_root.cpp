// The Q7.24 end-stop seat's search for x_r = +-travel on the step's polynomial
// (end_stop_detail::cubic_edge_root(), models/detail/end_stop_search.hpp): its trip count is a
// bound, kCubicStrokeNewtonSteps + F + 1 with F = 24 fraction bits, and within it the root is
// found to one unit of the last place, whatever the polynomial.
//
// The polynomials are x_r(u) = x0 + v0 u + a0 u^2/2 + jerk u^3/6 + snap u^4/24 (CubicSegment) with
// random coefficients of up to about 16 in scene units, crossing the edge x_r = 1 inside (0, hi]:
// rising ones, and ones that dip or flatten before they cross, where Newton's steps creep or
// leave the bracket and the search bisects. Searches whose arithmetic saturates the format are
// left out (their polynomial is not the one given).
#include <cmath>
#include <cstdint>
#include <random>

#include "CppUTest/TestHarness.h"
#include "stickslip/core/fixed_point32.hpp"
#include "stickslip/models/detail/end_stop_search.hpp"

using namespace stickslip;

namespace {

using F = Fixed32;
constexpr int kBound = end_stop_detail::kCubicStrokeNewtonSteps + F::kFractionBits + 1;

struct Search {
  bool valid = false;  // the edge is crossed inside (0, hi] and nothing saturated
  bool converged = false;
  int iterations = 0;
};

// f = x_r - 1 at u (raw units), and whether the search's root is within one unit of its sign
// change: |f| at most one unit there, or f changes sign between the root and a neighbour.
Search search(const CubicSegment<F>& segment, F hi) {
  Search out;
  const F edge(1.0), s(1.0);
  const auto f = [&](F u) { return s * (segment.position(u) - edge); };
  const F f_lo = f(F(0.0)), f_hi = f(hi);
  if (!(f_lo < F(0.0) && f_hi > F(0.0))) return out;
  (void)ScalarTraits<F>::take_saturation();
  const auto found = end_stop_detail::cubic_edge_root(segment, edge, s, hi, f_lo, f_hi);
  const F unit = F::from_raw(1);
  const F at = f(found.root), below = f(found.root - unit), above = f(found.root + unit);
  if (ScalarTraits<F>::take_saturation()) return out;
  out.valid = true;
  out.iterations = found.iterations;
  const bool small = at <= unit && at >= F(0.0) - unit;
  const bool changes = (below <= F(0.0) && at >= F(0.0)) || (at <= F(0.0) && above >= F(0.0));
  out.converged = small || changes;
  return out;
}

CubicSegment<F> from_raw(std::int32_t x0, std::int32_t v0, std::int32_t a0, std::int32_t jerk,
                         std::int32_t snap) {
  return CubicSegment<F>(F::from_raw(x0), F::from_raw(v0), F::from_raw(a0), F::from_raw(jerk),
                         F::from_raw(snap));
}

}  // namespace

TEST_GROUP(CubicEdgeRoot){};

TEST(CubicEdgeRoot, EveryRootIsWithinOneUnitAndTheSearchWithinItsBound) {
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  long searches = 0, bisecting = 0;
  int most = 0;
  for (int n = 0; n < 400000; ++n) {
    const double scale = std::pow(10.0, 1.2 * unit(random));
    const double x0 = 1.0 - std::fabs(unit(random)) * scale;
    const double v0 = 4.0 * scale * unit(random), a0 = 8.0 * scale * unit(random);
    const double jerk = 16.0 * scale * unit(random), snap = 32.0 * scale * unit(random);
    if (std::fabs(x0) > 100 || std::fabs(v0) > 100 || std::fabs(a0) > 100 ||
        std::fabs(jerk) > 100 || std::fabs(snap) > 100)
      continue;
    const Search result =
        search(CubicSegment<F>(F(x0), F(v0), F(a0), F(jerk), F(snap)), F(std::fabs(unit(random))));
    if (!result.valid) continue;
    ++searches;
    if (result.iterations > end_stop_detail::kCubicStrokeNewtonSteps + 10) ++bisecting;
    if (result.iterations > most) most = result.iterations;
    CHECK_TRUE(result.converged);
    CHECK(result.iterations <= kBound);
  }
  // The family exercises both phases: many searches bisect long after Newton's steps.
  CHECK(searches > 100000);
  CHECK(bisecting > 1000);
  CHECK(most >= kBound - 2);
}

// Found by climbing from the random family's slowest search: a quartic that flattens before it
// crosses, so that Newton's steps creep and leave over half the step to bisect.
TEST(CubicEdgeRoot, TheSlowestPolynomialFoundTakesExactlyTheBound) {
  const Search result = search(from_raw(2327126, 153661541, -828880709, 2138192050, 1478220767),
                               F::from_raw(16255259));
  CHECK_TRUE(result.valid);
  CHECK_TRUE(result.converged);
  CHECK_EQUAL(kBound, result.iterations);
}

// A contact as the seat makes it: x_r rising through the edge at a steady rate, Newton from the
// secant: a few iterations.
TEST(CubicEdgeRoot, ASteadyContactTakesAFewNewtonSteps) {
  const Search result = search(CubicSegment<F>(F(0.8), F(0.5), F(-0.2), F(0.05), F(0.0)), F(1.0));
  CHECK_TRUE(result.valid);
  CHECK_TRUE(result.converged);
  CHECK(result.iterations <= 3);
}
