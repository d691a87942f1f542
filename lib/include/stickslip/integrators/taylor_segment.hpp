// The exact solution inside one tick of the event search as a Taylor polynomial, and the first
// instant at which v_r changes sign along it. Used by the exact integrator, whose trajectory
// between the grid points is the exact solution itself: with the friction force held, the linear
// part x' = v, v' = -k/m x - b/m v + g(t) with g linear in t has Taylor coefficients that follow
// from a short recurrence, and `configure()` picks the tick size and the order so that the
// truncation error is below the rounding of the scalar type (see event_search_plan()).
//
// The event path is a chain of dependent operations (build, locate, evaluate), so polynomials are
// evaluated by Estrin's scheme (a depth of log2 of the degree instead of the degree) with the
// coefficients padded by zeros to a fixed degree.
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

#include "stickslip/core/scalar.hpp"

namespace stickslip {

// Highest degree of v_r(u) the plan may ask for; x_r(u) has one degree more.
inline constexpr int kMaxTaylorOrder = 10;
// The root search (falling_root()) takes Newton steps inside its bracket in its first
// kRootNewtonIterations<T> iterations and only bisects after them, so that its trip count is a
// bound rather than a cap. From its first iterate Newton needed at most 13 iterations in double
// and 11 in float (over 30 million searches: 2,160 random seats of omega0 dt 0.01 to 1.5, plain
// and with end stops, Coulomb and Stribeck, on white noise and random phases of up to 41 m/s^2;
// the reference seat with and without stops on lorry, wideband, harmonic and seat-test floors
// and on both firmware hardest sets), so the limits, 16 and 12, do not change where those
// searches end; where one runs out, the bisections still end within the tolerance. Float's is
// the lower because the Cortex-M4F's static bound charges every iteration of it
// (docs/EMBEDDED.md).
inline constexpr int kRootNewtonIterationsFloat = 12;
inline constexpr int kRootNewtonIterationsDouble = 16;
template <typename T>
inline constexpr int kRootNewtonIterations =
    std::numeric_limits<T>::digits <= 24 ? kRootNewtonIterationsFloat : kRootNewtonIterationsDouble;
// Bisections that take the bracket [lo, hi] (0 <= lo < hi) within the search's tolerance
// 4 eps (lo + hi) of the root: a midpoint halves the bracket to within one ulp of hi (at most
// eps hi), so after m of them it is within hi 2^-m + 2 eps hi of the root, inside the tolerance
// once 2^-m <= 2 eps: m = digits - 2 (22 in float, 51 in double). A bracket in the subnormal
// range (within 1e-38 of the tick's start in float) ends at the bound short of its tolerance.
// Fixed point never runs the Taylor search (ScalarTraits::kTaylorEventSearch).
template <typename T>
inline constexpr int kRootBisections =
    std::is_floating_point_v<T> ? std::numeric_limits<T>::digits - 2 : 0;
// The most iterations of one root search: at least kRootBisections of them bisect.
template <typename T>
inline constexpr int kMaxRootIterations = kRootNewtonIterations<T> + kRootBisections<T>;

// Recurrence coefficients for one tick length H, in the tick-normalised time u = tau / H:
//   X[n+1] = step[n] V[n],  V[n+1] = step[n] G[n] - stiffness[n] X[n] - damping[n] V[n]
// with step[n] = H/(n+1), stiffness[n] = H k/(m (n+1)), damping[n] = H b/(m (n+1)), G[0] = g0,
// G[1] = the input slope, G[n >= 2] = 0. From n = 2 on the recurrence is homogeneous, so every
// later coefficient is a fixed combination of V[1] and V[2]:
//   V[n] = v_from_v1[n] V[1] + v_from_v2[n] V[2],  X[n] = x_from_v1[n] V[1] + x_from_v2[n] V[2]
// (n >= 3), precomputed by configure(): the segment then builds its coefficients side by side
// instead of in a chain of `order` dependent steps.
template <typename T>
struct TaylorCoefficients {
  int order = 0;  // K: v_r to degree K; 0 when the plan uses linear interpolation instead
  T step[kMaxTaylorOrder + 1]{};
  T stiffness[kMaxTaylorOrder + 1]{};
  T damping[kMaxTaylorOrder + 1]{};
  T v_from_v1[kMaxTaylorOrder + 1]{}, v_from_v2[kMaxTaylorOrder + 1]{};
  T x_from_v1[kMaxTaylorOrder + 2]{}, x_from_v2[kMaxTaylorOrder + 2]{};
};

// Fills `c` for the tick length tick_s (the plan's order already in c.order), from the double
// coefficients (long double for the combinations, which are products of up to K factors).
template <typename T>
void fill_taylor_coefficients(TaylorCoefficients<T>& c, double tick_s, double stiffness_over_mass,
                              double damping_over_mass) noexcept {
  using Real = long double;
  Real step[kMaxTaylorOrder + 1], stiffness[kMaxTaylorOrder + 1], damping[kMaxTaylorOrder + 1];
  for (int n = 0; n <= kMaxTaylorOrder; ++n) {
    step[n] = static_cast<Real>(tick_s) / static_cast<Real>(n + 1);
    stiffness[n] = step[n] * static_cast<Real>(stiffness_over_mass);
    damping[n] = step[n] * static_cast<Real>(damping_over_mass);
    c.step[n] = static_cast<T>(step[n]);
    c.stiffness[n] = static_cast<T>(stiffness[n]);
    c.damping[n] = static_cast<T>(damping[n]);
  }
  // The homogeneous recurrence from (X[2], V[2]) = (step[1] V[1], V[2]) for the two bases, up to
  // the plan's order only (higher terms are negligible and could be subnormal in float).
  for (int basis = 0; basis < 2; ++basis) {
    Real x = basis == 0 ? step[1] : Real(0);  // X[2]
    Real v = basis == 0 ? Real(0) : Real(1);  // V[2]
    for (int n = 2; n <= c.order; ++n) {
      const Real x_next = step[n] * v;
      const Real v_next = -(stiffness[n] * x + damping[n] * v);
      x = x_next;
      v = v_next;
      (basis == 0 ? c.x_from_v1 : c.x_from_v2)[n + 1] = static_cast<T>(x);
      if (n + 1 <= c.order) (basis == 0 ? c.v_from_v1 : c.v_from_v2)[n + 1] = static_cast<T>(v);
    }
  }
}

// A polynomial of degree <= 11 with zero-padded coefficients. Low degrees (the float plans) by
// Horner's rule; from degree 6 on by Estrin's scheme, whose powers u^2, u^4, u^8 are flushed to
// zero where they would fall below the normal range (they could not change the sum there, and a
// subnormal would raise the underflow flag).
template <typename T>
struct PaddedPolynomial {
  static constexpr int kTerms = 12;
  static constexpr int kEstrinFromDegree = 6;
  int degree = 0;
  // Up to the degree; beyond it zero from kEstrinFromDegree on, where Estrin's scheme reads them
  // (Horner's rule reads none).
  T c[kTerms];

  PaddedPolynomial() noexcept : c{} {}
  // For a writer that sets the degree and the terms itself (derivative(), TaylorSegment): below
  // kEstrinFromDegree (the float plans) no padding is zeroed, which on the Cortex-M4F is a
  // memset call of about 100 instructions per polynomial, several per event.
  struct Unfilled {};
  explicit PaddedPolynomial(Unfilled) noexcept {}
  bool padded() const noexcept { return degree >= kEstrinFromDegree; }
  void zero_padding() noexcept {
    for (int n = 0; n < kTerms; ++n) c[n] = T(0);
  }

  T operator()(T u) const noexcept {
    if (degree < kEstrinFromDegree) {
      T sum = c[degree];
      for (int n = degree - 1; n >= 0; --n) sum = sum * u + c[n];
      return sum;
    }
    const T u2 = square(u);
    const T u4 = square(u2);
    const T q0 = c[0] + c[1] * u, q1 = c[2] + c[3] * u, q2 = c[4] + c[5] * u;
    const T q3 = c[6] + c[7] * u;
    const T r0 = q0 + q1 * u2, r1 = q2 + q3 * u2;
    if (degree < 8) return r0 + r1 * u4;
    const T u8 = square(u4);
    const T q4 = c[8] + c[9] * u, q5 = c[10] + c[11] * u;
    const T r2 = q4 + q5 * u2;
    return (r0 + r1 * u4) + r2 * u8;
  }
  PaddedPolynomial derivative() const noexcept {
    PaddedPolynomial d{Unfilled{}};
    d.degree = degree > 0 ? degree - 1 : 0;
    if (!padded()) {
      for (int n = 0; n < degree; ++n) d.c[n] = T(n + 1) * c[n + 1];
      return d;
    }
    // The padding's derivative is zero, as the padding is.
    for (int n = 0; n + 1 < kTerms; ++n) d.c[n] = T(n + 1) * c[n + 1];
    d.c[kTerms - 1] = T(0);
    return d;
  }

  // sqrt of the smallest normal number, rounded up to a power of two: a product of two numbers
  // at least this large is a normal number.
  static constexpr T square_floor() noexcept {
    T floor = T(1);
    for (int e = 0; e > std::numeric_limits<T>::min_exponent / 2; --e) floor *= T(0.5);
    return floor;
  }

 private:
  static T square(T a) noexcept { return ScalarTraits<T>::abs(a) < square_floor() ? T(0) : a * a; }
};

// The search's first iterate: where f's quadratic Taylor polynomial about lo falls through
// zero, if it does inside the bracket, else the secant through the ends. Where a slip starts
// or v_r turns, f is dominated by its curvature (a tiny f(lo) and f'(lo), a large f''): the
// secant then lands far short of the root, Newton's steps from there leave the bracket, and the
// search bisects its way to the root: up to 17 iterations in float on a minute of the
// Cortex-M4F's hardest input set (docs/EMBEDDED.md), and 2 at most from the quadratic's root.
template <typename T>
T falling_root_first_iterate(const PaddedPolynomial<T>& slope, const PaddedPolynomial<T>* curvature,
                             T sign, T lo, T hi, T at_lo, T at_hi) noexcept {
  const T secant = lo + (hi - lo) * (at_lo / (at_lo - at_hi));
  if constexpr (std::is_floating_point_v<T>) {
    if (curvature == nullptr) return secant;
    using S = ScalarTraits<T>;
    // f(lo) + b s + a s^2 with s = u - lo, f(lo) = at_lo > 0. Operands below the square floor
    // are taken as 0 (c: the secant), so that every product is a normal number or exactly 0
    // and no underflow is raised; the root from its stable form 2 c / (sqrt(D) - b).
    const T floor = PaddedPolynomial<T>::square_floor();
    const T c = at_lo;
    if (!(c >= floor)) return secant;
    T b = sign * (lo == T(0) ? slope.c[0] : slope(lo));
    const T curve = sign * (lo == T(0) ? curvature->c[0] : (*curvature)(lo));
    if (S::abs(b) < floor) b = T(0);
    const T a = S::abs(curve) < floor ? T(0) : T(0.5) * curve;  // >= floor / 2 or 0
    const T discriminant = b * b - (T(4) * a) * c;
    if (!(discriminant >= T(0))) return secant;
    const T denominator = std::sqrt(discriminant) - b;
    // At least the floor: the quotient stays finite (c is a velocity, far below 2^60).
    if (!(denominator >= floor)) return secant;
    const T u = lo + (c + c) / denominator;
    return u > lo && u < hi ? u : secant;
  } else {
    (void)slope;
    (void)curvature;
    (void)sign;
    return secant;
  }
}

// A root of the search below and the iterations it took (each one evaluation of f and f').
template <typename T>
struct FallingRoot {
  T root;
  int iterations;
};

// Root of f = sign * p in (lo, hi) given f(lo) > 0 > f(hi), with f' = sign * slope: Newton
// from the secant through the ends, kept inside the bracket (bisection where Newton would leave
// it; the step is tested against the bracket by multiplication, so nothing overflows or divides
// by zero). With f'' = sign * curvature known, Newton's error after a step s is about
// |f''/(2 f')| s^2: once that is below a few ulp of the interval the step is the answer,
// without another evaluation to confirm it; otherwise it stops when the step is that small, or
// the bracket is within its tolerance, after at most kMaxRootIterations<T> iterations. The
// bisections after the Newton phase are a loop of their own that evaluates f alone, so that a
// static bound charges them one evaluation each, not Newton's three (port/baremetal/
// loop-bounds.json).
template <typename T>
FallingRoot<T> falling_root(const PaddedPolynomial<T>& p, const PaddedPolynomial<T>& slope,
                            const PaddedPolynomial<T>* curvature, T sign, T lo, T hi, T at_lo,
                            T at_hi) noexcept {
  using S = ScalarTraits<T>;
  const T tolerance = T(4) * S::epsilon() * (S::abs(lo) + S::abs(hi));
  const T inv_tolerance = tolerance > T(0) ? T(1) / tolerance : T(0);
  T u = falling_root_first_iterate(slope, curvature, sign, lo, hi, at_lo, at_hi);
  int iteration = 0;
  while (iteration < kRootNewtonIterations<T>) {
    ++iteration;
    const T value = sign * p(u);
    const T gradient = sign * slope(u);
    if (value == T(0)) return {u, iteration};
    // Selects rather than branches: the sign of f at the iterate is data.
    lo = value > T(0) ? u : lo;
    hi = value < T(0) ? u : hi;
    // Newton's step -value/gradient stays inside (lo, hi) iff -value lies strictly between
    // gradient (hi - u) and gradient (lo - u) (gradient < 0: f falls through its root).
    if (gradient < T(0) && -value < gradient * (lo - u) && -value > gradient * (hi - u)) {
      const T step = -value / gradient;
      const T next = u + step;
      // |f''| s^2 <= 2 |f'| tolerance (as (|f''| |s|) (|s| / tolerance), so that no tiny
      // square underflows).
      const T size = S::abs(step);
      if (size <= tolerance ||
          (curvature != nullptr &&
           (S::abs((*curvature)(u)) * size) * (size * inv_tolerance) <= T(2) * S::abs(gradient))) {
        return {next, iteration};
      }
      u = next;
    } else {
      u = lo + (hi - lo) * T(0.5);
    }
    if (hi - lo <= tolerance) return {u, iteration};
  }
  while (iteration < kMaxRootIterations<T>) {
    ++iteration;
    const T value = sign * p(u);
    if (value == T(0)) return {u, iteration};
    lo = value > T(0) ? u : lo;
    hi = value < T(0) ? u : hi;
    u = lo + (hi - lo) * T(0.5);
    if (hi - lo <= tolerance) break;
  }
  return {u, iteration};
}

// x_r(u) = sum X[n] u^n and v_r(u) = sum V[n] u^n from a given state, u in tick units.
template <typename T>
class TaylorSegment {
 public:
  // From the state (x0, v0), with the generalised input g(u) = g0 + g_slope u (friction held).
  // `starting_direction` != 0: a slip phase starts here in that direction, where the stick
  // decision guarantees a_r d >= 0; a negative initial acceleration is rounding and is clamped.
  TaylorSegment(const TaylorCoefficients<T>& c, T x0, T v0, T g0, T g_slope,
                T starting_direction) noexcept
      : x_{typename PaddedPolynomial<T>::Unfilled{}}, v_{typename PaddedPolynomial<T>::Unfilled{}} {
    const int order = c.order;
    x_.degree = order + 1;
    v_.degree = order;
    if (x_.padded()) x_.zero_padding();
    if (v_.padded()) v_.zero_padding();
    T* x = x_.c;
    T* v = v_.c;
    x[0] = x0;
    v[0] = v0;
    x[1] = c.step[0] * v0;
    T v1 = c.step[0] * g0 - c.stiffness[0] * x0 - c.damping[0] * v0;
    if (v1 * starting_direction < T(0)) v1 = T(0);
    v[1] = v1;
    x[2] = c.step[1] * v1;
    const T v2 = c.step[1] * g_slope - c.stiffness[1] * x[1] - c.damping[1] * v1;
    v[2] = v2;
    for (int n = 3; n <= order; ++n) v[n] = c.v_from_v1[n] * v1 + c.v_from_v2[n] * v2;
    for (int n = 3; n <= order + 1; ++n) x[n] = c.x_from_v1[n] * v1 + c.x_from_v2[n] * v2;
  }

  T position(T u) const noexcept { return x_(u); }
  T velocity(T u) const noexcept { return v_(u); }

  // The u in (lo, hi) at which x_r reaches `edge`, given s (x_r - edge) < 0 at lo (`at_lo`) and
  // > 0 at hi (`at_hi`): falling_root() on -s (x_r - edge), so within its tolerance after at most
  // kMaxRootIterations<T> iterations.
  T edge_crossing(T edge, T s, T lo, T hi, T at_lo, T at_hi) const noexcept {
    PaddedPolynomial<T> offset = x_;
    offset.c[0] = x_.c[0] - edge;
    const PaddedPolynomial<T> slope = x_.derivative();
    const PaddedPolynomial<T> curvature = slope.derivative();
    return falling_root(offset, slope, &curvature, -s, lo, hi, -at_lo, -at_hi).root;
  }

  // The first u in (lo, hi] at which v_r d turns negative, given v_r(lo) d >= 0 (`at_lo`):
  // a sign change at hi, or a dip (v_r d falls, crosses zero and may rise again) inside.
  // Returns false if v_r d stays >= 0 on the whole interval.
  bool first_crossing(T d, T lo, T hi, T at_lo, T& root) const noexcept {
    const T at_hi = d * v_(hi);
    if (at_hi < T(0)) {
      const PaddedPolynomial<T> a = v_.derivative();
      const PaddedPolynomial<T> jerk = a.derivative();
      if (!(at_lo > T(0))) {
        // At rest at lo (a slip that starts here): where it first moves in d (a d > 0 at lo)
        // the crossing is the fall after its one maximum inside, not lo; else lo.
        root = lo;
        const T rising_lo = d * a(lo);
        const T rising_hi = d * a(hi);
        if (!(rising_lo > T(0) && rising_hi < T(0))) return true;
        const T maximum = falling_root<T>(a, jerk, nullptr, d, lo, hi, rising_lo, rising_hi).root;
        const T at_maximum = d * v_(maximum);
        if (at_maximum > T(0)) {
          root = falling_root(v_, a, &jerk, d, maximum, hi, at_maximum, at_hi).root;
        }
        return true;
      }
      root = falling_root(v_, a, &jerk, d, lo, hi, at_lo, at_hi).root;
      return true;
    }
    // No sign change at the ends: a crossing needs a minimum of v_r d inside (a(lo) d < 0 <
    // a(hi) d), where v_r d < 0. At most one extremum per step (omega0 dt <= pi/2).
    const PaddedPolynomial<T> a = v_.derivative();
    const T falling_lo = -d * a(lo);  // -(v_r d)' falls through the minimum
    const T falling_hi = -d * a(hi);
    if (!(falling_lo > T(0) && falling_hi < T(0))) return false;
    const PaddedPolynomial<T> jerk = a.derivative();
    const T minimum = falling_root<T>(a, jerk, nullptr, -d, lo, hi, falling_lo, falling_hi).root;
    const T at_minimum = d * v_(minimum);
    if (!(at_minimum < T(0))) return false;
    root = at_lo > T(0) ? falling_root(v_, a, &jerk, d, lo, minimum, at_lo, at_minimum).root : lo;
    return true;
  }

 private:
  PaddedPolynomial<T> x_;  // degree order + 1
  PaddedPolynomial<T> v_;  // degree order
};

}  // namespace stickslip
