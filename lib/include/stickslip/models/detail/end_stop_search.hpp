// The in-step event search of EndStopOscillator (models/end_stops.hpp): the definitions of the
// members end_stops.hpp declares for it.
//
// One engine for every mode boundary: v_r = 0 while slipping (stick or reversal), |x_r| = travel
// (contact from the free stroke, release from a stop) and, while stuck, |F_L| = F_fs
// (break-away). The mode's exact affine maps scan the step on its grid of 2^16 ticks (16 blocks,
// then bisection down to the tick whose end leaves the mode, or, where |v_r| fell and rose again
// inside a block, down to the tick of its turn, where v_r may cross 0 and back between the
// block's ends); inside that tick the mode's exact motion is its Taylor polynomial (order
// chosen in configure() so that the truncation is below the scalar's rounding), on which the
// boundary is solved for: v_r = 0 by TaylorSegment's first_crossing (a dip to 0 and back
// included), x_r = +-travel by TaylorSegment::edge_crossing (the same root search,
// falling_root(), on x_r - travel). Break-away is solved for directly (F_L is linear in time). A
// position inside the step is whole ticks plus a fraction of the next, so the step's end is
// reached exactly.
//
// Loop bounds (the step's work): at most kEventBudget events (one more than the exact solution's
// 9 for Coulomb stick-slip and 6 without friction, step_common.hpp; Stribeck's kMaxEventsPerStep;
// fewer where the law declares fewer: CTest EndStopEventBudget.* reaches it), then one pass to the
// step's end without a search; per event one scan of at most 16 blocks, one bisection of 12 levels,
// one Taylor tick (its root searches run at most kMaxRootIterations<T> iterations each,
// integrators/taylor_segment.hpp), and the rest of the tick the event's search starts in; one block
// of the scan whose |v_r| dips adds a bisection of at most 12 levels and one Taylor tick, and a
// second scan of the rest of the step (at most one such block per event: move_to_mode_end(), which
// so solves at most two ticks itself, its start's and a dip's). Q7.24 (one tick per step): per
// event one cubic polynomial, its v_r root search (kCubicRootNewtonSteps) and the stroke boundary's
// (end_stop_detail::cubic_edge_root(): at most kCubicStrokeNewtonSteps + 25).
#pragma once

#include "stickslip/models/end_stops.hpp"

namespace stickslip {

namespace end_stop_detail {
// Q7.24 (one tick per step), x_r = +-travel on the cubic: Newton from the secant in the first
// kCubicStrokeNewtonSteps iterations, each doubling the digits (3 iterations at most in
// tests/host/test_end_stop_fixed32.cpp and on 60 s of 30 m/s^2 white noise with 320 contacts),
// the bracket's midpoint after them and wherever a step would leave it.
inline constexpr int kCubicStrokeNewtonSteps = 4;

template <typename T>
struct EdgeRoot {
  T root;
  int iterations;
};

// The u in (0, hi) at which f = s (x_r(u) - edge) rises through 0, given f(0) = f_lo < 0 <
// f(hi) = f_hi, to one unit of the last place of f or of u. A midpoint halves the bracket, which
// is at most the step wide (2^F units of the last place, F = T::kFractionBits): after the Newton
// iterations, F midpoints bring it to one unit, where the search stops at one of its ends, so the
// loop runs at most kCubicStrokeNewtonSteps + F + 1 times (CTest CubicEdgeRoot.* reaches that).
template <typename T>
EdgeRoot<T> cubic_edge_root(const CubicSegment<T>& segment, T edge, T s, T hi, T f_lo,
                            T f_hi) noexcept {
  using S = ScalarTraits<T>;
  constexpr int kMaxIterations = kCubicStrokeNewtonSteps + T::kFractionBits + 1;
  T lo = T(0);
  T u = hi * S::proportion(-f_lo, f_hi - f_lo);
  int iteration = 0;
  // Newton's iterations, then the midpoints in a loop of their own that evaluates x_r alone, so
  // that a static bound charges them one evaluation each, not Newton's v_r and proportion too
  // (port/baremetal/loop-bounds.json).
  while (iteration < kCubicStrokeNewtonSteps) {
    ++iteration;
    const T f = s * (segment.position(u) - edge);
    if (S::abs(f) <= S::epsilon()) return {u, iteration};
    if (f > T(0)) {
      hi = u;
    } else {
      lo = u;
    }
    if (hi - lo <= S::epsilon()) return {u, iteration};
    T next = lo;
    // Newton's step where it lands inside the bracket (x_r s rises: slope > 0).
    const T slope = s * segment.velocity(u);
    const T size = S::abs(f);
    if (slope > T(0) && size <= slope) {
      const T change = S::proportion(size, slope);
      next = f > T(0) ? u - change : u + change;
    }
    if (!(next > lo && next < hi)) next = lo + S::divide_by_power_of_two(hi - lo, 1);
    if (next == u) return {u, iteration};
    u = next;
  }
  while (iteration < kMaxIterations) {
    ++iteration;
    const T f = s * (segment.position(u) - edge);
    if (S::abs(f) <= S::epsilon()) break;
    if (f > T(0)) {
      hi = u;
    } else {
      lo = u;
    }
    if (hi - lo <= S::epsilon()) break;
    const T next = lo + S::divide_by_power_of_two(hi - lo, 1);
    if (next == u) break;
    u = next;
  }
  return {u, iteration};
}
}  // namespace end_stop_detail

template <typename T, typename Law>
int EndStopOscillator<T, Law>::search(const Input& in, T& stuck_fraction,
                                      StopContacts<T>& out) noexcept {
  Position pos{0u, T(0)};
  int events = 0;
  while (pos.tick < kTicks) {
    const bool detect = events < kEventBudget;
    if (!detect) ++counters_.event_budget_exhausted;  // the rest of the step without events
    if (kSticking && direction_ == T(0)) {
      if (!detect) {
        stuck_fraction += T(1) - phi(pos);
        return events;
      }
      if (!break_away(in, pos, stuck_fraction)) return events;
      refresh_force();  // Stribeck: the slip begins at rest, with F_fs
      ++events;
      continue;
    }
    const Boundary boundary = move_to_mode_end(in, pos, detect);
    if (boundary == Boundary::none) return events;
    ++events;
    enter_mode_at(in, pos, boundary, out);
    refresh_force();  // Stribeck: the next piece's force, from the event's state
  }
  return events;
}

// Stuck at pos: F_L is linear in time; false (stuck to the end of the step) when it holds,
// otherwise true with pos at the instant |F_L| reaches F_fs and the seat leaving against F_L.
template <typename T, typename Law>
bool EndStopOscillator<T, Law>::break_away(const Input& in, Position& pos,
                                           T& stuck_fraction) noexcept {
  const T phi_now = phi(pos);
  const T f1 = limit_force(x_, in.a1);
  const T a_now = in.at(phi_now);
  const T f0 = limit_force(x_, a_now);
  v_ = T(0);
  if (S::abs(f0) > holding_limit_n(x_, a_now)) {
    // Beyond F_fs already at pos: only at a step's start, where a change of the actuator force
    // makes F_L jump (elsewhere the seat stuck because F_L held there). It leaves at once.
    direction_ = f0 > T(0) ? T(-1) : T(1);
    return true;
  }
  if (S::abs(f1) <= static_n_) {
    stuck_fraction += T(1) - phi_now;
    return false;
  }
  // F_L reaches the bound on f1's side; it may start at F_fs on that side already (held within
  // the rounding of its terms: it leaves at once) or on the other (F_L falls through the band
  // |F_L| <= F_fs before it breaks away).
  const T bound = f1 > T(0) ? static_n_ : -static_n_;
  T ratio = T(0);
  if (f1 > T(0) ? f0 < bound : f0 > bound) {  // f0 short of the bound, f1 beyond: f1 != f0
    ratio = S::proportion(bound - f0, f1 - f0);
    ratio = ratio < T(0) ? T(0) : (ratio > T(1) ? T(1) : ratio);
  }
  const T phi_break = phi_now + ratio * (T(1) - phi_now);
  stuck_fraction += phi_break - phi_now;
  // The break-away as ticks after pos, which keeps a fraction of a tick to the scalar's
  // precision. Through phi it would keep the step's: in float late in a step 1/256 of a tick, and
  // rounding could put the break-away before pos, where the seat stuck, to slip back and stick
  // again at once there until the event budget ran out.
  const T ticks = pos.frac + ratio * (T(kTicks - pos.tick) - pos.frac);
  unsigned whole = pos.tick + static_cast<unsigned>(ticks);
  if (whole >= kTicks) whole = kTicks;
  pos.frac = whole >= kTicks ? T(0) : ticks - T(whole - pos.tick);
  pos.tick = whole;
  direction_ = f1 > T(0) ? T(-1) : T(1);
  return true;
}

// Moving from pos in the current mode: to the first boundary (returned, with the state and pos
// there) or to the end of the step (Boundary::none). Without `detect`, straight to the end.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::move_to_mode_end(
    const Input& in, Position& pos, bool detect) noexcept {
  law_detail::count_loop_run<Law>(LoopRun::mode_search);
  T x = x_, v = v_;
  if (pos.frac > T(0)) {
    law_detail::count_loop_run<Law>(LoopRun::mode_tick);
    const Boundary inside = within_tick(in, pos, x, v, detect);
    x_ = x;
    v_ = v;
    // With one tick per step (Q7.24) the tick's end is the step's: stated at compile time, so
    // that the scan's path after it, which cannot run, is not compiled (nor charged by the static
    // bound a tick solve of its own on top of this one).
    if (kTicks == 1u || inside != Boundary::none || pos.tick >= kTicks) return inside;
  }
  unsigned end = pos.tick;
  // The scan stops at a block where |v_r| fell and rose again (v_r may cross 0 and back between
  // its ends; the plain seat's search bisects such a block too). There bisection follows the turn
  // of v_r, a_r d changing sign, down to its tick, unless a half's end leaves the mode first, and
  // the tick's polynomial finds the crossing, a dip to 0 and back included. a_r changes sign at
  // most once a step in one mode: it solves the mode's homogeneous equation, a_r'' + (b/m) a_r' +
  // (k/m) a_r = 0 (the input's slope and the friction are constant over the piece), whose zeros
  // lie pi/omega_d >= 2 dt apart (configure(): omega0 dt <= pi/2, free and in contact). So one
  // dipping block is searched, and the scan runs at most twice: before it and after it.
  // The search for a dip needs a_r at a block's end only where |v_r| falls at its start, and the
  // end of one block is the start of the next: at most one a_r a block.
  bool dip_searched = !(kSticking && detect);
  T a_start = T(0);
  bool a_start_known = false;
  for (int scan = 0; scan < 2 && end < kTicks; ++scan) {
    unsigned next = end;
    T xn = x, vn = v;
    bool dipping = false;
    while (end < kTicks) {
      law_detail::count_loop_run<Law>(LoopRun::scan_block);
      next = (end / kScanBlock + 1) * kScanBlock;
      if (span_leaves_mode(in, x, v, end, next - end, xn, vn, true) && detect) {
        const unsigned lo = first_tick_leaving_mode(in, end, next, x, v, xn, vn);
        return leave_at_tick(in, lo, x, v, xn, vn, pos);
      }
      if (kSticking && !dip_searched) {
        if (!a_start_known) a_start = acceleration_along_slip(x, v, end, in);
        a_start_known = a_start < T(0);
        if (a_start_known) {
          const T a_end = acceleration_along_slip(xn, vn, next, in);
          if (dips(in, x, v, end, next, a_start, a_end)) {
            dipping = true;
            break;
          }
          a_start = a_end;
        }
      }
      x = xn;
      v = vn;
      end = next;
    }
    if (!dipping) break;
    dip_searched = true;
    unsigned lo = end, hi = next;
    T xl = x, vl = v, a_lo = a_start;
    while (hi - lo > 1) {
      law_detail::count_loop_run<Law>(LoopRun::dip_bisection);
      const unsigned mid = lo + (hi - lo) / 2;
      T xm, vm;
      if (span_leaves_mode(in, xl, vl, lo, mid - lo, xm, vm, false)) {
        lo = first_tick_leaving_mode(in, lo, mid, xl, vl, xm, vm);
        return leave_at_tick(in, lo, xl, vl, xm, vm, pos);
      }
      const T a_mid = acceleration_along_slip(xm, vm, mid, in);
      if (dips(in, xl, vl, lo, mid, a_lo, a_mid)) {
        hi = mid;
      } else {
        lo = mid;
        xl = xm;
        vl = vm;
        a_lo = a_mid;
      }
    }
    Position at{lo, T(0)};
    law_detail::count_loop_run<Law>(LoopRun::mode_tick);
    const Boundary found = within_tick(in, at, xl, vl, true);
    if (found != Boundary::none) {
      x_ = xl;
      v_ = vl;
      pos = at;
      return found;
    }
    // No crossing on the polynomial: the block holds the mode to its end.
    x = xn;
    v = vn;
    end = next;
  }
  if constexpr (kTicks > kScanBlock) {
    if (pos.tick == 0u && pos.frac == T(0)) {
      // The whole step in one mode (a turn of v_r that reached no boundary): its one map, as the
      // common path's, rounds once where the scan's blocks round once each, and the blocks'
      // errors add up over a run (undamped contacts: 40 times the energy drift). The scan's end
      // stands where rounding puts the map's end across a boundary the scan did not see.
      T whole_x = x_, whole_v = v_;
      advance(whole_x, whole_v, contact_, slip_force(), 0u, kTicks, in);
      if (!mode_ends(whole_x, whole_v)) {
        x = whole_x;
        v = whole_v;
      }
    }
  }
  x_ = x;
  v_ = v;
  pos = Position{kTicks, T(0)};
  return Boundary::none;
}

// The scan left the mode at the end of tick `lo`, whose start state is (x, v) and end state by
// the maps (xn, vn): the boundary inside it, the state and pos there.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::leave_at_tick(
    const Input& in, unsigned lo, T x, T v, T xn, T vn, Position& pos) noexcept {
  Position at{lo, T(0)};
  Boundary found = within_tick(in, at, x, v, true);
  if (found == Boundary::none) {
    // The polynomial stays in the mode where the maps leave it: they differ by rounding (in
    // float one tick can move x_r by less than its ulp), and the boundary is the tick's end, of
    // the kind the maps saw there.
    x = xn;
    v = vn;
    at = Position{lo + 1, T(0)};
    found = stroke_ends(x) ? Boundary::stroke : Boundary::velocity;
  }
  x_ = x;
  v_ = v;
  pos = at;
  return found;
}

// A block of the slip from (x, v) at tick `at` to tick `next` that does not leave the mode, with
// a_r d at its ends (acceleration_along_slip()): whether |v_r| fell and rose again in between
// (a_r d < 0 at the start, > 0 at the end), so that v_r may have crossed 0 and back. A block that
// starts at rest to within the rounding of its terms (a slip's start, a_r d >= 0 to rounding) is
// no dip (see rest_rounding_velocity()).
template <typename T, typename Law>
bool EndStopOscillator<T, Law>::dips(const Input& in, T x, T v, unsigned at, unsigned next,
                                     T a_start, T a_end) const noexcept {
  return a_start < T(0) && a_end > T(0) &&
         !(S::abs(v) <= rest_rounding_velocity(x, at, next - at, in));
}

// From pos to the end of its tick, or (with `detect`) to the first boundary inside it: returns
// which, with (x, v) and pos there. Floating point solves for it on the mode's Taylor polynomial;
// fixed point (no Taylor search) interpolates inside the tick of dt/2^16, whose second-order
// error (tick^2 jerk, ~1e-16 of the motion) is far below its resolution.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::within_tick(
    const Input& in, Position& pos, T& x, T& v, bool detect) const noexcept {
  if constexpr (S::kTaylorEventSearch) {
    return within_tick_taylor(in, pos, x, v, detect);
  } else if constexpr (S::kCubicEventSearch) {
    return within_tick_cubic(in, pos, x, v, detect);
  } else {
    return within_tick_interpolated(in, pos, x, v, detect);
  }
}

// Fixed point: a second-order Taylor step over the rest of the tick; a boundary inside it (v_r d
// reaching 0, x_r reaching the stroke boundary) is placed by linear interpolation.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::within_tick_interpolated(
    const Input& in, Position& pos, T& x, T& v, bool detect) const noexcept {
  const int mode = contact_ != 0 ? 1 : 0;
  const T span = T(1) - pos.frac;
  const T h = span * tick_s_;
  const T a = seat_acceleration(x, v) - in.at(phi(pos));
  const T jerk =
      -(stiffness_over_mass_[mode] * v + damping_over_mass_[mode] * a) - (in.a1 - in.a0) / dt_s_;
  const T x_end = x + h * (v + T(0.5) * a * h);
  T v_end = v + h * (a + T(0.5) * jerk * h);
  const bool starting = kSticking && v == T(0);
  // A slip that starts here departs with a d >= 0: a reversed end is rounding.
  if (starting && v_end * direction_ < T(0)) v_end = T(0);
  Boundary found = Boundary::none;
  T theta = T(1);  // the boundary's place in the rest of the tick
  if (detect) {
    if (kSticking && !starting && v_end * direction_ <= T(0)) {
      theta = S::proportion(v, v - v_end);
      found = Boundary::velocity;
    }
    const StrokeCrossing c = stroke_crossing(x, x_end);
    if (c.leaves) {
      const T at = c.f_lo < T(0) ? S::proportion(-c.f_lo, c.f_hi - c.f_lo) : T(0);
      if (found == Boundary::none || at < theta) {
        theta = at;
        found = Boundary::stroke;
      }
    }
    theta = theta < T(0) ? T(0) : (theta > T(1) ? T(1) : theta);
  }
  if (found == Boundary::none) {
    x = x_end;
    v = v_end;
    ++pos.tick;
    pos.frac = T(0);
    return found;
  }
  x = x + theta * (x_end - x);
  v = found == Boundary::velocity ? T(0) : v + theta * (v_end - v);
  pos.frac = pos.frac + theta * span;
  if (!(pos.frac < T(1))) {
    ++pos.tick;
    pos.frac = T(0);
  }
  return found;
}

// Floating point: on the mode's Taylor polynomial.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::within_tick_taylor(
    const Input& in, Position& pos, T& x, T& v, bool detect) const noexcept {
  // On x_r from the mode's anchor, as the maps (frame_of()): the tick agrees with them.
  const ModeFrame frame = frame_of(contact_, x, slip_force());
  const T span = T(1) - pos.frac;
  const T starting = kSticking && v == T(0) ? direction_ : T(0);
  const TaylorSegment<T> segment(taylor_[contact_ != 0 ? 1 : 0], frame.local(x), v,
                                 -(in.at(phi(pos)) + frame.offset),
                                 -(in.a1 - in.a0) * tick_fraction_, starting);
  T end = span;
  Boundary found = Boundary::none;
  if (detect) {
    if constexpr (kSticking) {
      T root = T(0);
      if (segment.first_crossing(direction_, T(0), span, v * direction_, root)) {
        end = root;
        found = Boundary::velocity;
      }
    }
    const StrokeCrossing c = stroke_crossing(x, frame.x_r(segment.position(end)));
    if (c.leaves) {
      // On the edge already at the tick's start (f_lo = 0): the boundary is here.
      end = c.f_lo < T(0)
                ? segment.edge_crossing(frame.local(c.edge), c.s, T(0), end, c.f_lo, c.f_hi)
                : T(0);
      found = Boundary::stroke;
    }
  }
  const Boundary result = end_on_segment(segment, found, end, pos, x, v);
  x = frame.x_r(x);
  return result;
}

// Scene units, one tick per step (Q7.24): on the mode's cubic polynomial of the exact solution
// over the rest of the step (integrators/cubic_segment.hpp), as Oscillator's search. v_r = 0 by
// CubicSegment::first_crossing() (a dip to 0 and back included); x_r = +-travel by Newton on x_r's
// polynomial from the secant, kept inside its bracket (the slope is v_r, dt = 1), stopping where
// x_r is on the edge to one unit of the last place or the step stalls.
template <typename T, typename Law>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::within_tick_cubic(
    const Input& in, Position& pos, T& x, T& v, bool detect) const noexcept {
  // Compiled for the scalars whose traits offer the cubic search only (within_tick() calls it for
  // them alone; the explicit instantiations of the others compile every member).
  if constexpr (S::kCubicEventSearch) {
    const int mode = contact_ != 0 ? 1 : 0;
    const T span = T(1) - pos.frac;
    T a = seat_acceleration(x, v) - in.at(phi(pos));
    const bool starting = kSticking && v == T(0);
    // A slip that starts here departs with a d >= 0 (the stick decision): the opposite is rounding.
    if (starting && a * direction_ < T(0)) a = T(0);
    const T jerk =
        -(stiffness_over_mass_[mode] * v + damping_over_mass_[mode] * a) - (in.a1 - in.a0);
    const T snap = -(stiffness_over_mass_[mode] * a + damping_over_mass_[mode] * jerk);
    const CubicSegment<T> segment(x, v, a, jerk, snap);
    T end = span;
    Boundary found = Boundary::none;
    if (detect) {
      if constexpr (kSticking) {
        T root = T(0);
        if (segment.first_crossing(direction_, span, root)) {
          end = root;
          found = Boundary::velocity;
        }
      }
      const StrokeCrossing c = stroke_crossing(x, segment.position(end));
      if (c.leaves) {
        // On the edge already at the step's start (f_lo = 0): the boundary is here.
        end = c.f_lo < T(0)
                  ? end_stop_detail::cubic_edge_root(segment, c.edge, c.s, end, c.f_lo, c.f_hi).root
                  : T(0);
        found = Boundary::stroke;
      }
    }
    return end_on_segment(segment, found, end, pos, x, v);
  } else {
    (void)in, (void)pos, (void)x, (void)v, (void)detect;
    return Boundary::none;
  }
}

// The end of a within-tick solve on a segment of the mode's exact motion (TaylorSegment,
// CubicSegment): the state at `end` (the boundary `found`, or the tick's end), v_r = 0 at a
// velocity boundary, and pos there.
template <typename T, typename Law>
template <typename Segment>
typename EndStopOscillator<T, Law>::Boundary EndStopOscillator<T, Law>::end_on_segment(
    const Segment& segment, Boundary found, T end, Position& pos, T& x, T& v) noexcept {
  x = segment.position(end);
  v = found == Boundary::velocity ? T(0) : segment.velocity(end);
  if (found == Boundary::none) {
    ++pos.tick;
    pos.frac = T(0);
  } else {
    pos.frac = pos.frac + end;
    if (!(pos.frac < T(1))) {
      ++pos.tick;
      pos.frac = T(0);
    }
  }
  return found;
}

// Advances (x, v) at tick `at` by `count` ticks to (xn, vn); true where the mode has ended there.
// Floating point, slipping: a span that starts and ends at rest to within the rounding of its
// acceleration terms (rest_rounding_velocity()) ends at rest, vn = 0, with no velocity event; the
// scan and its bisection judge a span by this one rule, so the bisection cannot settle on a tick
// whose reversal of v_r is rounding where the scan's block saw a genuine one further on. Q7.24
// (one tick per step) clamps the start of a slip on its cubic instead (within_tick_cubic()).
// `rest_rule` false: the rule is known not to apply (a bisection of a block that did not start at
// rest), and its rounding is not formed.
template <typename T, typename Law>
bool EndStopOscillator<T, Law>::span_leaves_mode(const Input& in, T x, T v, unsigned at,
                                                 unsigned count, T& xn, T& vn,
                                                 bool rest_rule) const noexcept {
  xn = x;
  vn = v;
  advance(xn, vn, contact_, slip_force(), at, count, in);
  if constexpr (kSticking && !kCubic) {
    if (rest_rule && vn * direction_ <= T(0)) {  // only where v_r would end the mode
      const T rounding = rest_rounding_velocity(x, at, count, in);
      if (S::abs(v) <= rounding && S::abs(vn) <= rounding) {
        vn = T(0);
        return stroke_ends(xn);
      }
    }
  }
  return mode_ends(xn, vn);
}

// Bisects (lo, hi], where the state (x, v) at tick lo fits the mode and the one at hi (x_hi,
// v_hi) does not, down to one tick; returns its start, with (x, v) advanced to it and (x_hi,
// v_hi) the state the maps put at its end.
template <typename T, typename Law>
unsigned EndStopOscillator<T, Law>::first_tick_leaving_mode(const Input& in, unsigned lo,
                                                            unsigned hi, T& x, T& v, T& x_hi,
                                                            T& v_hi) const noexcept {
  // The rest rule applies where the block started at rest to within its rounding; a block that
  // did not holds a genuine slip, whose halves are judged by the sign of v_r alone.
  bool from_rest = false;
  if constexpr (kSticking && !kCubic) {
    from_rest = hi - lo > 1 && S::abs(v) <= rest_rounding_velocity(x, lo, hi - lo, in);
  }
  while (hi - lo > 1) {
    const unsigned mid = lo + (hi - lo) / 2;
    T xm, vm;
    if (span_leaves_mode(in, x, v, lo, mid - lo, xm, vm, from_rest)) {
      hi = mid;
      x_hi = xm;
      v_hi = vm;
    } else {
      lo = mid;
      x = xm;
      v = vm;
    }
  }
  return lo;
}

// At pos a mode ended: at a stroke boundary the seat enters or leaves a stop (x_r on the edge,
// v_r carried on); at v_r = 0 it sticks if friction can hold it, else reverses.
template <typename T, typename Law>
void EndStopOscillator<T, Law>::enter_mode_at(const Input& in, const Position& pos,
                                              Boundary boundary, StopContacts<T>& out) noexcept {
  if (boundary == Boundary::stroke) {
    const T edge = boundary_ahead(x_);
    x_ = edge;
    if (contact_ == 0) {
      contact_ = edge > T(0) ? 1 : -1;
      ++contacts_;
      if (out.contact_events == 0) out.first_contact_s = phi(pos) * dt_s_;
      ++out.contact_events;
    } else {
      contact_ = 0;
    }
    return;
  }
  if constexpr (kSticking) {
    const T a_u = in.at(phi(pos));
    const T f = limit_force(x_, a_u);
    v_ = T(0);
    direction_ = S::abs(f) <= holding_limit_n(x_, a_u) ? T(0) : (f > T(0) ? T(-1) : T(1));
  }
}

}  // namespace stickslip
