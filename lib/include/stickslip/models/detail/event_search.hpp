// The in-step event search of Oscillator (models/oscillator.hpp) and the rare paths of its step
// that run it: the definitions of the members oscillator.hpp declares for them.
//
// An event is an instant inside the step where the friction changes: v_r reaches 0 while
// slipping (stick or reversal), or the limit force reaches F_fs while stuck (break-away). While
// slipping, a sign change of v_r inside the step is located by bisection on the dyadic grid of
// the step (the maps of dt/2^l are precomputed) down to a tick, inside which the exact integrator
// solves the Taylor polynomial of the exact solution (Newton steps on the polynomial,
// integrators/taylor_segment.hpp) and the other integrators interpolate linearly. While stuck,
// F_L is linear in time, so the break-away instant is solved for directly. A position inside the
// step is kept as whole ticks plus a fraction of the next tick, so that the step's end is reached
// exactly.
//
// Q7.24 (ScalarTraits::kCubicEventSearch) takes the whole step as one tick and finds the crossing
// on the cubic polynomial of the exact solution over it (finish_tick_cubic()): no bisection.
//
// The work of one step is bounded by the trip counts of its loops (L = event_level_: 16 in
// floating point, 10 in Q23.40, 0 in Q7.24):
//   - step_sticking()'s and step_held()'s event loops: at most kEventBudget + 1 passes (each pass
//     but the last locates one event; at the budget the step finishes in its mode, counted where
//     that lost an event: stuck with |F_L| beyond F_fs at the end, or v_r against the direction):
//     the exact solution's own 3 for a slip force constant over each piece of motion
//     (step_common.hpp), every law and scalar, and kMaxEventsPerStep = 32 for Stribeck under RK4,
//     whose stages follow v_r (with end stops, end_stop_search.hpp: 10 for Coulomb);
//   - slip()'s block walk: at most 2^(L+1) - 1 block maps per step over all its calls, since the
//     walk only moves forward and evaluates each dyadic block of the step at most once (it starts
//     at a position only on blocks that start there); every run of its body maps a block before
//     it can return an event, so the body runs at most that often per step, the runs that return
//     included (the static bound charges them once per step, port/baremetal/loop-bounds.json);
//     lowest_set_bit(): at most L shifts;
//   - finish_tick_taylor(): at most 2 passes (the second after the start guard), once per slip
//     phase; TaylorSegment::first_crossing(): at most two root searches (a dip's minimum and its
//     root) of at most kMaxRootIterations<T> iterations each (34 in float, 67 in double: Newton's,
//     then a loop of bisections);
//     proportion(): F shift-and-subtract rounds (fixed point);
//   - searches of a tick's polynomial (first_crossing(), every scalar): at most
//     kEventBudget / 2 + 2^L per step in step_sticking(), (kEventBudget - 1) + 2^L in
//     step_held(). A pass that slips from inside a tick searches it once (finish_tick_*()); the
//     first pass starts at the step's start, not inside a tick nor at a slip's start (Q7.24
//     excepted, whose one tick the first pass searches in place of a walk), and the pass past
//     the budget searches nothing (d = 0); in step_sticking() neither does a slip from rest
//     towards the way F_L moves (every break-away inside the step: it cannot return to rest in
//     it) nor one right after a slip from rest that was searched, so at most kEventBudget / 2 of
//     the passes below the budget search (one in two of passes 1 to kEventBudget - 1), where
//     step_held() searches in each of them. The block walks search a tick at most once per
//     step, since they move on past it. At L = 0 (the firmware's plan, and Q7.24) that is 2 for
//     the budget of 3, which the static bound charges per step rather than per pass
//     (port/baremetal/loop-bounds.json "calls");
//   - Q7.24: no block walk; finish_tick_cubic() once per slip phase, its root search at most
//     kCubicRootNewtonSteps Newton steps from the root of its quadratic part (and one
//     proportion for a dip's minimum).
// docs/EMBEDDED.md gives what these cost on the Cortex-M targets and the worst frame measured.
#pragma once

#include "stickslip/integrators/cubic_segment.hpp"
#include "stickslip/integrators/taylor_segment.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/step_common.hpp"
#include "stickslip/models/whole_step.hpp"

namespace stickslip {

// Classic RK4 with the friction force evaluated at every stage (velocity-dependent laws).
template <typename T, typename Law>
template <typename Force>
inline void Oscillator<T, Law>::advance_rk4(T& x, T& v, int level, T a_u0, T a_u1,
                                            const Force& force) const noexcept {
  const T h = block_s_[level];
  const T half_h = kHalf * h;
  const T a_mid = kHalf * (a_u0 + a_u1);
  const T k1x = v;
  const T k1v = relative_acceleration(x, v, force(v), a_u0);
  const T x2 = x + half_h * k1x, v2 = v + half_h * k1v;
  const T k2v = relative_acceleration(x2, v2, force(v2), a_mid);
  const T x3 = x + half_h * v2, v3 = v + half_h * k2v;
  const T k3v = relative_acceleration(x3, v3, force(v3), a_mid);
  const T x4 = x + h * v3, v4 = v + h * k3v;
  const T k4v = relative_acceleration(x4, v4, force(v4), a_u1);
  const T sixth_h = h * (T(1) / T(6));
  x = x + sixth_h * (k1x + T(2) * (v2 + v3) + v4);
  v = v + sixth_h * (k1v + T(2) * (k2v + k3v) + k4v);
}

// One block of 2^(event_level_ - level) ticks starting at `tick`.
template <typename T, typename Law>
template <typename Force>
inline void Oscillator<T, Law>::advance_block(T& x, T& v, unsigned tick, int level, const Input& in,
                                              const Force& force) const noexcept {
  const unsigned size = ticks_per_step_ >> level;
  const T a_u0 = in.at(T(tick) * inv_ticks_);
  const T a_u1 = in.at(T(tick + size) * inv_ticks_);
  // (Known false at compile time for a law without velocity dependence: no RK4 code in its
  // step.)
  if (Law::velocity_dependent && stage_friction_) {
    advance_rk4(x, v, level, a_u0, a_u1, force);
  } else {
    // Friction held over the block at its value at the block start.
    const T scaled_force = inv_mass_ * force(v);
    advance_affine(x, v, level, -(a_u0 + scaled_force), -(a_u1 + scaled_force));
  }
}

template <typename T, typename Law>
inline int Oscillator<T, Law>::lowest_set_bit(unsigned value) noexcept {
  int bit = 0;
  while ((value & 1u) == 0u) {
    value >>= 1u;
    ++bit;
  }
  return bit;
}

// The rounding of v_r over a block of `level` started near rest: 8 ulp of the velocity change
// each acceleration term alone would make (spring, friction, input at both ends) over it.
// A block or tick that starts at rest to rounding (a slip start, or a clamp) with the seat
// balanced at the break-away limit (a_r ~ 0) ends with a v_r of either sign by rounding alone,
// and the search would put an "event" near its start (linear interpolation; on the Taylor
// polynomial, at the start itself), spending an event per tick with no progress (float
// stick-slip and Stribeck scenes would exhaust their event budget so). A crossing within that
// rounding is no event: v_r is clamped at 0 (also when it stays positive: a speck of 1e-33 m/s
// would only feed denormal products, FE_UNDERFLOW in float). A genuine stick still shows once a_r
// exceeds the rounding of its terms.
template <typename T, typename Law>
inline T Oscillator<T, Law>::rest_rounding_velocity(int level, T x, T force_n, T a_u_start,
                                                    const Input& in) const noexcept {
  const T terms = S::abs(k_over_m_ * x) + S::abs(inv_mass_ * force_n) + S::abs(a_u_start) +
                  S::abs(in.a0) + S::abs(in.a1);
  return T(8) * S::epsilon() * block_s_[level] * terms;
}

template <typename T, typename Law>
inline void Oscillator<T, Law>::advance_within_tick(Position& pos, T fraction) noexcept {
  pos.frac = fraction;
  if (!(pos.frac < T(1))) {
    ++pos.tick;
    pos.frac = T(0);
  }
}

// The end of a tick's finish on a segment of the exact solution (TaylorSegment, CubicSegment)
// started at u_start in the tick: at `root` with v_r = 0 if a crossing was found there, else at
// the tick's end. Returns `found`.
template <typename T, typename Law>
template <typename Segment>
inline bool Oscillator<T, Law>::end_on_segment(const Segment& segment, bool found, T root,
                                               T u_start, Position& pos, T& x, T& v) noexcept {
  if (found) {
    x = segment.position(root);
    v = T(0);
    advance_within_tick(pos, u_start + root);
    return true;
  }
  x = segment.position(T(1) - u_start);
  v = segment.velocity(T(1) - u_start);
  ++pos.tick;
  pos.frac = T(0);
  return false;
}

// Exact integrator: from `pos` inside a tick (or at a slip start) to the end of that tick on
// the Taylor polynomial of the exact solution, with the friction force_n held. Returns true
// with v_r = 0 and `pos` at the first instant where v_r d turns negative (d != 0; not searched
// for PieceStart::kFromRestNoReturn).
template <typename T, typename Law>
inline bool Oscillator<T, Law>::finish_tick_taylor(Position& pos, T& x, T& v, T d, const Input& in,
                                                   T force_n, PieceStart start) const noexcept {
  const T scaled_force = inv_mass_ * force_n;
  const bool search = start != PieceStart::kFromRestNoReturn;
  bool starting = start != PieceStart::kInPhase;
  for (;;) {
    const T u_start = pos.frac;
    const T span = T(1) - u_start;
    const TaylorSegment<T> segment(taylor_, x, v, -(in.at(phi(pos)) + scaled_force),
                                   input_slope_per_tick(in), starting ? d : T(0));
    if (d != T(0)) {
      T lo = T(0);
      T at_lo = v * d;
      if (starting) {
        // A slip phase begins here with a_r d >= 0: within its first 1/2^kEventLevels of the
        // step a sign change can only be rounding (a_r ~ 0 when |F_L| ~ F_fs). v_r is clamped
        // at 0 there instead of letting it fake an event, and the search goes on from there.
        lo = start_guard_ticks_ < span ? start_guard_ticks_ : span;
        at_lo = segment.velocity(lo) * d;
        if (at_lo < T(0)) {
          x = segment.position(lo);
          v = T(0);
          advance_within_tick(pos, u_start + lo);
          if (pos.frac == T(0)) return false;
          starting = false;
          continue;
        }
      }
      // At rest at lo and at the tick's end to within the rounding of the acceleration terms:
      // no event, v_r clamped at 0 (as the block loop's rule).
      if (!(at_lo > T(0))) {
        const T rounding = rest_rounding_velocity(event_level_, x, force_n, in.at(phi(pos)), in);
        const T v_end = segment.velocity(span);
        if (v_end * d < T(0) && S::abs(v_end) <= rounding && S::abs(v) <= rounding) {
          x = segment.position(span);
          v = T(0);
          ++pos.tick;
          pos.frac = T(0);
          return false;
        }
      }
      if (search) {
        T root = T(0);
        law_detail::count_loop_run<Law>(LoopRun::tick_search);
        const bool found = segment.first_crossing(d, lo, span, at_lo, root);
        return end_on_segment(segment, found, root, u_start, pos, x, v);
      }
    }
    return end_on_segment(segment, false, T(0), u_start, pos, x, v);
  }
}

// The other integrators (and fixed point): from `pos` inside a tick (or at a slip start) to the
// end of that tick with a second-order Taylor step, friction force_n held; a sign change of v_r d
// is placed by linear interpolation (not for PieceStart::kFromRestNoReturn). Returns true with
// v_r = 0 and `pos` at that instant.
template <typename T, typename Law>
inline bool Oscillator<T, Law>::finish_tick_interpolated(Position& pos, T& x, T& v, T d,
                                                         const Input& in, T force_n,
                                                         PieceStart start) const noexcept {
  const bool starting = start != PieceStart::kInPhase;
  const T h = (T(1) - pos.frac) * tick_s_;
  const T a = relative_acceleration(x, v, force_n, in.at(phi(pos)));
  const T jerk = -(k_over_m_ * v + b_over_m_ * a) - by_unit(inv_dt_, in.a1 - in.a0);
  const T x_end = x + h * (v + kHalf * a * h);
  T v_end = v + h * (a + kHalf * jerk * h);
  if (starting && v_end * d < T(0)) v_end = T(0);
  // At rest to rounding (see slip()'s block loop): 0, not a denormal-bound speck.
  if (S::abs(v) <= rest_rounding_velocity(event_level_, x, force_n, in.at(phi(pos)), in) &&
      S::abs(v_end) <= rest_rounding_velocity(event_level_, x, force_n, in.at(phi(pos)), in))
    v_end = T(0);
  if (start != PieceStart::kFromRestNoReturn && v_end * d < T(0)) {
    const T theta = S::proportion(v, v - v_end);
    x = x + theta * (x_end - x);
    v = T(0);
    advance_within_tick(pos, pos.frac + theta * (T(1) - pos.frac));
    return true;
  }
  x = x_end;
  v = v_end;
  ++pos.tick;
  pos.frac = T(0);
  return false;
}

// Fixed point with one tick per step (ScalarTraits::kCubicEventSearch): from `pos` inside the
// tick (or at a slip start) to its end on the cubic Taylor polynomial of the exact solution
// (integrators/cubic_segment.hpp), friction force_n held, as finish_tick_taylor() does with its
// polynomial. Returns true with v_r = 0 and `pos` at the first instant where v_r d turns negative
// (not searched for PieceStart::kFromRestNoReturn). `a_u_at_pos`: a_u at `pos`, where the caller
// has it (the instant of the event that ended the last pass), else null.
template <typename T, typename Law>
inline bool Oscillator<T, Law>::finish_tick_cubic(Position& pos, T& x, T& v, T d, const Input& in,
                                                  T force_n, PieceStart start,
                                                  const T* a_u_at_pos) const noexcept {
  // Compiled for the scalars whose traits offer the cubic search only (slip() calls this for
  // them alone; the explicit instantiations of the others compile every member).
  if constexpr (S::kCubicEventSearch) {
    const T span = T(1) - pos.frac;
    T a = relative_acceleration(x, v, force_n,
                                a_u_at_pos != nullptr ? *a_u_at_pos : input_at(in, phi(pos)));
    // A slip phase starts at rest with a_r d >= 0 (the stick decision): the opposite sign is
    // rounding. (The search from rest needs no start guard: see CubicSegment::first_crossing().)
    if (start != PieceStart::kInPhase && a * d < T(0)) a = T(0);
    const T jerk = -(k_over_m_ * v + b_over_m_ * a) - by_unit(inv_dt_, in.a1 - in.a0);
    const T snap = -(k_over_m_ * a + b_over_m_ * jerk);
    const CubicSegment<T> segment(x, v, a, jerk, snap);
    T root = T(0);
    const bool search = d != T(0) && start != PieceStart::kFromRestNoReturn;
    if (search) law_detail::count_loop_run<Law>(LoopRun::tick_search);
    const bool found = search && segment.first_crossing(d, span, root);
    return end_on_segment(segment, found, root, pos.frac, pos, x, v);
  } else {
    (void)pos, (void)x, (void)v, (void)d, (void)in, (void)force_n, (void)start, (void)a_u_at_pos;
    return false;
  }
}

// Integrates from `pos` to the end of the step with the given friction. With direction d != 0,
// stops at the first instant where v_r*d turns negative: returns true with v_r = 0 and `pos` at
// that instant. d = 0 integrates to the end without looking for events.
// `start` other than kInPhase: the slip phase begins here (break-away or reversal), where
// a_r*d >= 0 by the stick decision; its first 1/2^kEventLevels of the step cannot hold a genuine
// crossing, so v_r*d is clamped at 0 there instead of letting rounding (a_r ~ 0 when
// |F_L| ~ F_fs) fake one. kFromRestNoReturn: clamped so, then integrated to the end without
// looking for events.
// `whole_step`: the common path's whole step from the start of the step, if it was computed.
// `a_u_at_pos`: a_u at `pos`, if the caller has it; the cubic search takes it instead of
// interpolating the input again (two products in Q7.24), the other searches interpolate.
template <typename T, typename Law>
template <typename Force>
inline bool Oscillator<T, Law>::slip(Position& pos, T& x, T& v, T d, const Input& in,
                                     const Force& force, PieceStart start,
                                     const WholeSlip<T>* whole_step,
                                     const T* a_u_at_pos) const noexcept {
  if constexpr (S::kCubicEventSearch) {
    // One tick per step: its polynomial finds the crossing, a dip included, with no block maps.
    (void)whole_step;
    return pos.tick < ticks_per_step_ &&
           finish_tick_cubic(pos, x, v, d, in, force(v), start, a_u_at_pos);
  }
  (void)a_u_at_pos;
  if (pos.tick < ticks_per_step_ && (pos.frac > T(0) || start != PieceStart::kInPhase)) {
    if (taylor_search()) {
      if (finish_tick_taylor(pos, x, v, d, in, force(v), start)) return true;
    } else if (finish_tick_interpolated(pos, x, v, d, in, force(v), start)) {
      return true;
    }
  }
  if (start == PieceStart::kFromRestNoReturn) d = T(0);  // the rest of the step: no search
  while (pos.tick < ticks_per_step_) {
    law_detail::count_loop_run<Law>(LoopRun::block_walk);
    // The largest dyadic block aligned at pos.tick (the whole step from the start).
    int level = pos.tick == 0u ? 0 : event_level_ - lowest_set_bit(pos.tick);
    const T force_start = force(v);
    const T a_u_start = in.at(T(pos.tick) * inv_ticks_);
    const T a_start = relative_acceleration(x, v, force_start, a_u_start);
    for (;;) {
      const unsigned size = ticks_per_step_ >> level;
      T x_end = x, v_end = v;
      const bool known = whole_step != nullptr && pos.tick == 0u && level == 0;
      if (known) {
        x_end = whole_step->x;
        v_end = whole_step->v;
      } else {
        advance_block(x_end, v_end, pos.tick, level, in, force);
      }
      bool crossed = v_end * d < T(0);
      // A crossing within the rounding of a block started at rest is no event, and v_r is
      // clamped at 0 (see rest_rounding_velocity()).
      const T rounding = rest_rounding_velocity(level, x, force_start, a_u_start, in);
      if (S::abs(v) <= rounding && S::abs(v_end) <= rounding) {
        v_end = T(0);
        crossed = false;
      }
      bool dip = false;  // |v| fell and rose again inside the block: it may have crossed twice
      if (!crossed && a_start * d < T(0)) {
        const T a_end = known ? whole_step->a_end
                              : relative_acceleration(x_end, v_end, force(v_end),
                                                      in.at(T(pos.tick + size) * inv_ticks_));
        dip = a_end * d > T(0);
      }
      if (crossed || dip) {
        if (level < event_level_) {
          ++level;  // bisect: try the first half
          continue;
        }
        // Inside one tick.
        if (taylor_search()) {
          const TaylorSegment<T> segment(taylor_, x, v, -(a_u_start + inv_mass_ * force_start),
                                         input_slope_per_tick(in), T(0));
          T root = T(0);
          law_detail::count_loop_run<Law>(LoopRun::tick_search);
          if (segment.first_crossing(d, T(0), T(1), v * d, root)) {
            x = segment.position(root);
            v = T(0);
            advance_within_tick(pos, root);
            return true;
          }
          if (crossed) {  // the polynomial and the map disagree only by rounding: at the end
            x = x_end;
            v = T(0);
            ++pos.tick;
            return true;
          }
        } else if (crossed) {
          const T theta = S::proportion(v, v - v_end);  // linear inside one tick
          x = x + theta * (x_end - x);
          v = T(0);
          advance_within_tick(pos, theta);
          return true;
        }
        // A dip without a crossing: accepted.
      }
      x = x_end;
      v = v_end;
      pos.tick += size;
      break;
    }
  }
  return false;
}

// Held laws (signum, smoothed): friction from the state at the start of the step. With the exact
// integrator a sign change of v_r inside the step is located and the friction re-sampled there
// with the law's value at rest (signum: the Filippov value clamp(F_L, +-F_fk), i.e. hold the load
// or reverse against it; smoothed: 0). Friction then never does positive work: the scheme is
// passive. Explicit integrators follow Simulink ode1 (no event location).
template <typename T, typename Law>
int Oscillator<T, Law>::step_held(const Input& in) noexcept {
  int events = 0;
  T force = held_force_;
  if (stage_friction_) {
    advance_rk4(x_, v_, 0, in.a0, in.a1, [this](T v) noexcept { return Law::force(v, friction_); });
  } else if (held_events_ && force != T(0)) {
    Position pos{0u, T(0)};
    T d = signum(v_);
    PieceStart start = PieceStart::kInPhase;
    bool unsearched = false;  // at the budget: the rest of the step slips without a search
    while (slip(pos, x_, v_, d, in, ConstantForce{force}, start)) {
      ++events;
      force = Law::force_at_rest(limit_force(in.at(phi(pos)), x_), friction_);
      // Slipping again only if the friction saturates against the load; otherwise held at rest
      // for the rest of the step (no further events to look for).
      const bool saturated = S::abs(force) == friction_.kinetic_n && force != T(0);
      unsearched = saturated && events >= event_budget();
      d = saturated && !unsearched ? signum(force) : T(0);
      start = d != T(0) ? PieceStart::kFromRest : PieceStart::kInPhase;
    }
    // Counted where the budget lost an event: the unsearched slip ended against its direction.
    if (unsearched && v_ * force < T(0)) ++counters_.event_budget_exhausted;
  } else {
    const T scaled_force = inv_mass_ * force;
    advance_affine(x_, v_, 0, -(in.a0 + scaled_force), -(in.a1 + scaled_force));
  }
  held_force_ = Law::force(v_, friction_);
  // Reported at the sample: with events, the friction acting at the end of the step (the
  // trajectory's own); otherwise the law at the sample, as ode1 reports it.
  reported_force_ = held_events_ ? force : held_force_;
  return events;
}

// The common path's whole slipping step, out of line for a scalar that asks for a compact
// stack (ScalarTraits::kCompactStack: the M0+ build): its temporaries then take no room in the
// frame on top of which the event search runs, which starts again from the step's start (the
// same operations, so the same bits). True, with `out`, when the step had no event.
template <typename T, typename Law>
bool Oscillator<T, Law>::whole_step_slips(const Input& in, StepOutput<T>& out) noexcept {
  const T force = Law::slip_force(v_, direction_, friction_);
  const WholeSlip<T> moved = whole_step_slip(
      maps_[0], k_over_m_, b_over_m_, by_unit(inv_mass_, force), x_, v_, slip_a_x_, in.a0, in.a1);
  if (slip_step_has_event(moved, direction_)) return false;
  x_ = moved.x;
  v_ = moved.v;
  slip_a_x_ = moved.seat_acceleration;
  write_slip_output(out, force, moved.seat_acceleration);
  return true;
}

// One piece of slip motion, from `pos` in direction_ to its first event or the step's end (see
// slip()). Stribeck's force follows v_r: with the friction held (every integrator but RK4, which
// evaluates the law at its stages) it is held over the whole piece at its value where the piece
// starts (the step's start, a break-away or a reversal), as over a step without events, not
// re-sampled at the blocks the event search happens to visit, so the trajectory does not depend
// on the search's grid (and EndStopOscillator's, out of reach of its stops, is this one).
template <typename T, typename Law>
inline bool Oscillator<T, Law>::slip_piece(Position& pos, T d, const Input& in, PieceStart start,
                                           const WholeSlip<T>* whole_step,
                                           const T* a_u_at_pos) noexcept {
  if constexpr (Law::velocity_dependent) {
    if (!stage_friction_) {
      const ConstantForce held{Law::slip_force(v_, direction_, friction_)};
      return slip(pos, x_, v_, d, in, held, start, whole_step, a_u_at_pos);
    }
  }
  return slip(pos, x_, v_, d, in, SlipForce{&friction_, direction_}, start, whole_step, a_u_at_pos);
}

// Stick-slip and Stribeck: the event loop of one step. `whole_step`: the common path's whole
// slipping step (Coulomb), when it found an event.
template <typename T, typename Law>
int Oscillator<T, Law>::step_sticking(const Input& in, T& stuck_fraction,
                                      const WholeSlip<T>* whole_step) noexcept {
  Position pos{0u, T(0)};
  int events = 0;
  bool starting = false;            // a slip phase begins at pos (after break-away or reversal)
  bool searched_from_rest = false;  // the step's last slip from rest looked for a return to rest
  // a_u and F_L at pos, where the slip that found the event there computed them for its decision:
  // the pass that follows starts from the same instant and state.
  bool at_event = false;
  T a_u_at_event = T(0);
  T limit_at_event = T(0);
  for (;;) {
    if (direction_ == T(0)) {
      // Stuck: F_L is linear in time inside the step; check the end, then solve for break-away.
      const T limit_end = limit_force(in.a1, x_);
      const T phi_now = phi(pos);
      // Held to the end if F_L is within F_fs at the end and now; now needs a test only at the
      // step's start, where an actuator force that changed makes F_L jump (inside the step F_L
      // is continuous and the stick decision left it within F_fs).
      const bool held = S::abs(limit_end) <= friction_.static_n &&
                        (pos.tick != 0u || pos.frac != T(0) ||
                         S::abs(limit_force(in.a0, x_)) <= friction_.static_n);
      if (held || events >= event_budget()) {
        // At the budget the seat stays stuck to the end; counted where that lost a break-away.
        if (!held) ++counters_.event_budget_exhausted;
        stuck_fraction += T(1) - phi_now;
        return events;
      }
      const T a_u_now = at_event ? a_u_at_event : input_at(in, phi_now);
      const T limit_now = at_event ? limit_at_event : limit_force(a_u_now, x_);
      T d = signum(limit_end);
      // F_L reaches F_fs on limit_end's side between now and the end: the denominator is non-zero
      // because limit_now is short of that threshold and limit_end beyond it. It may start on
      // the threshold already (within the rounding the stick decision allows: break away now) or
      // in the band on the other side (F_L falls through the band before it breaks away).
      T ratio = T(0);
      // d = +-1: its product is a sign.
      const T threshold = d < T(0) ? -friction_.static_n : friction_.static_n;
      if (S::abs(limit_now) > holding_limit_n(a_u_now, x_)) {
        // Beyond F_fs already (an actuator force that changed at the sample: F_L jumps there):
        // break away the way F_L points now.
        d = signum(limit_now);
      } else if (d > T(0) ? limit_now < threshold : limit_now > threshold) {
        ratio = S::proportion(threshold - limit_now, limit_end - limit_now);
        ratio = ratio < T(0) ? T(0) : (ratio > T(1) ? T(1) : ratio);
      }
      // Stuck from the step's start, the usual case, the rest of the step is all of it: in
      // scene units its product by 1 is skipped.
      const T phi_break =
          kSceneUnits && phi_now == T(0) ? ratio : phi_now + ratio * (T(1) - phi_now);
      stuck_fraction += phi_break - phi_now;
      // (Not by_unit(): its operand's conversion would still be made, and may flag saturation.)
      const T ticks = kSceneUnits ? phi_break : phi_break * T(ticks_per_step_);
      unsigned whole = static_cast<unsigned>(ticks);
      if (whole >= ticks_per_step_) whole = ticks_per_step_;
      pos.tick = whole;
      pos.frac = whole >= ticks_per_step_ ? T(0) : ticks - T(whole);
      direction_ = d;
      v_ = T(0);
      ++events;
      starting = true;
      at_event = false;
      continue;
    }
    const bool detect = events < event_budget();
    // A slip that starts from rest towards the way F_L moves over the step (at fixed x_r), or
    // with F_L constant, does not return to rest in it (step_common.hpp): every break-away inside
    // the step, since F_L reaches F_fs moving towards it. It runs to the step's end unsearched: a
    // return found there would be rounding's (a_r ~ 0 where |F_L| ~ F_fs), sticking the seat to
    // break it away again at once. So only a slip from rest against that way is searched, and
    // never two in a row: after one, the exact solution's next slip from rest goes with F_L (a
    // reversal turns the slip, a break-away inside the step goes with F_L), so a second would be
    // rounding's too. The searches of a step are then at most kEventBudget / 2 from rest (one
    // pass in two below the budget) and the first pass's.
    PieceStart start = PieceStart::kInPhase;
    if (starting) {
      const bool against = direction_ * (in.a0 - in.a1) < T(0);
      start =
          against && !searched_from_rest ? PieceStart::kFromRest : PieceStart::kFromRestNoReturn;
      searched_from_rest = start == PieceStart::kFromRest;
    }
    const T d = detect ? direction_ : T(0);
    if (!slip_piece(pos, d, in, start, events == 0 ? whole_step : nullptr,
                    at_event ? &a_u_at_event : nullptr)) {
      // At the budget the slip runs to the end unsearched; counted where it lost an event (v_r
      // ended against its direction).
      if (!detect && v_ * direction_ < T(0)) ++counters_.event_budget_exhausted;
      return events;
    }
    ++events;
    // v_r reached 0: stick if the limit force is within static friction (to its rounding), else
    // reverse.
    a_u_at_event = input_at(in, phi(pos));
    limit_at_event = limit_force(a_u_at_event, x_);
    at_event = true;
    direction_ =
        S::abs(limit_at_event) <= holding_limit_n(a_u_at_event, x_) ? T(0) : signum(limit_at_event);
    starting = direction_ != T(0);
  }
}

}  // namespace stickslip
