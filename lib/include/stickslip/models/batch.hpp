// N independent Coulomb stick-slip seats stepped together, for parameter sweeps: each lane has its
// own parameters (any integrator) and its own input sample, and its results equal those of a
// single Oscillator<T, CoulombStickSlip> with the same parameters and inputs, bit for bit.
//
// The state is kept as structure of arrays. A step first runs the common path for every lane in
// one branch-free loop that the compiler vectorises (whole_step.hpp, the very functions the single
// oscillator's step uses): a whole step stuck, or a whole step slipping without a sign change of
// v_r. Both candidates are computed for every lane and one is selected per lane. A lane whose step
// has an event (break-away, stick, reversal, a possible double crossing), a non-finite input or a
// non-finite state is then redone by its own Oscillator from the state before the step, so the
// event search is exactly the single oscillator's.
//
// No heap: the batch holds its N oscillators (for their coefficients and the event path) and the
// arrays: about 2.3 kB per lane in double, 1.3 kB in float.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/whole_step.hpp"

namespace stickslip {

template <typename T, std::size_t N>
class StickSlipBatch {
  static_assert(N >= 1, "a batch has at least one lane");
  using S = ScalarTraits<T>;
  // An unsigned integer of T's size, for selections by bit mask (see blend()).
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
  static_assert(sizeof(Bits) == sizeof(T), "blend() needs an unsigned integer of T's size");

 public:
  using Scalar = T;
  using Lane = Oscillator<T, CoulombStickSlip>;
  static constexpr std::size_t kLanes = N;

  // Configures one lane (params.model must be stick_slip) and leaves it reset to rest with
  // a_u = 0. A refused lane keeps its previous configuration. Every lane must be configured
  // before the first step.
  ConfigResult configure(std::size_t lane, const OscillatorParams& params) noexcept {
    ConfigResult result = lanes_[lane].configure(params);
    if (!result.ok()) return result;
    const Lane& o = lanes_[lane];
    const StepMap<T>& m = coefficients(o.maps_[0]);
    xx_[lane] = m.xx;
    xv_[lane] = m.xv;
    vx_[lane] = m.vx;
    vv_[lane] = m.vv;
    gx0_[lane] = m.gx0;
    gx1_[lane] = m.gx1;
    gv0_[lane] = m.gv0;
    gv1_[lane] = m.gv1;
    if constexpr (kSplit) {
      identity_x_[lane] = o.maps_[0].identity_x;
      identity_v_[lane] = o.maps_[0].identity_v;
    }
    k_over_m_[lane] = o.k_over_m_;
    b_over_m_[lane] = o.b_over_m_;
    // (1/m) F_fk: times d = +-1 it is bit for bit the single oscillator's (1/m)(F_fk d).
    kinetic_accel_[lane] = o.inv_mass_ * o.friction_.kinetic_n;
    kinetic_n_[lane] = o.friction_.kinetic_n;
    static_n_[lane] = o.friction_.static_n;
    mass_kg_[lane] = o.mass_kg_;
    stiffness_[lane] = o.stiffness_;
    dt_s_[lane] = o.dt_s_;
    load(lane);
    return result;
  }

  // As Oscillator::reset() for one lane.
  void reset(std::size_t lane, T x0_m, T v0_m_per_s, T a_u0) noexcept {
    lanes_[lane].reset(x0_m, v0_m_per_s, a_u0);
    load(lane);
  }

  // Advances every lane by one sample: lane i from its previous input to a_u[i].
  void step(const T (&a_u)[N]) noexcept {
    const State& now = state_[current_];
    State& next = state_[current_ ^ 1u];
    // The common path of every lane in one loop without branches, which the compiler vectorises:
    // both candidates (a whole step stuck, a whole step slipping) are computed for every lane and
    // one is selected by bit masks (blend()), which leaves no condition that the compiler could
    // turn into a branch (it would not if-convert floating-point operations back). The state is
    // read from one set of arrays and written to the other, so every store is unconditional.
    for (std::size_t i = 0; i < N; ++i) {
      const T raw = a_u[i];
      const bool finite_input = finite_quietly(raw);
      const T a0 = now.a_prev[i];
      const T a1 = finite_input ? raw : a0;
      const T x = now.x[i], v = now.v[i], d = direction_[i];
      const Bits stuck = stuck_mask_[i];
      const StepMap<T> rest{xx_[i], xv_[i], vx_[i], vv_[i], gx0_[i], gx1_[i], gv0_[i], gv1_[i]};
      const Map map = lane_map(rest, i);
      const WholeSlip<T> moved = whole_step_slip(map, k_over_m_[i], b_over_m_[i],
                                                 kinetic_accel_[i] * d, x, v, now.a_x[i], a0, a1);
      const T limit = stuck_limit_force(mass_kg_[i], stiffness_[i], x, a1);
      const T slip_event = (slip_step_has_event(moved, d) | !finite_input) ? T(1) : T(0);
      const T stuck_event =
          (stuck_step_breaks_away(limit, static_n_[i]) | !finite_input) ? T(1) : T(0);
      next.x[i] = blend(stuck, x, moved.x);
      next.v[i] = blend(stuck, v, moved.v);
      next.a_prev[i] = a1;
      next.a_x[i] = blend(stuck, a1, moved.seat_acceleration);
      friction_n_[i] = blend(stuck, limit, kinetic_n_[i] * d);
      const T stuck_fraction = blend(stuck, T(1), T(0));
      stuck_fraction_[i] = stuck_fraction;
      // 0/1 flags combined arithmetically (exact): a bit-mask blend of two compare results would
      // need a conversion SSE2 lacks.
      redo_[i] = stuck_fraction * stuck_event + (T(1) - stuck_fraction) * slip_event;
    }
    current_ ^= 1u;
    T any_event = T(0);
    for (std::size_t i = 0; i < N; ++i) any_event += redo_[i];
    for (std::size_t i = 0; i < N; ++i) events_[i] = 0;
    if (any_event == T(0)) return;
    for (std::size_t i = 0; i < N; ++i) {
      if (redo_[i] != T(0)) redo(i, a_u[i]);
    }
  }

  // The same input sample for every lane.
  void step(T a_u) noexcept {
    T all[N];
    for (std::size_t i = 0; i < N; ++i) all[i] = a_u;
    step(all);
  }

  // The outputs of the last step, lane by lane (what Oscillator::step() returned).
  T x_r(std::size_t lane) const noexcept { return state_[current_].x[lane]; }
  T v_r(std::size_t lane) const noexcept { return state_[current_].v[lane]; }
  T a_x(std::size_t lane) const noexcept { return state_[current_].a_x[lane]; }
  T friction_n(std::size_t lane) const noexcept { return friction_n_[lane]; }
  T stuck_fraction(std::size_t lane) const noexcept { return stuck_fraction_[lane]; }
  T stuck_time_s(std::size_t lane) const noexcept { return stuck_fraction_[lane] * dt_s_[lane]; }
  bool stuck(std::size_t lane) const noexcept { return direction_[lane] == T(0); }
  std::uint8_t events(std::size_t lane) const noexcept { return events_[lane]; }
  StepOutput<T> output(std::size_t lane) const noexcept {
    StepOutput<T> out{};
    out.x_r_m = x_r(lane);
    out.v_r_m_per_s = v_r(lane);
    out.a_x_m_per_s2 = a_x(lane);
    out.friction_n = friction_n_[lane];
    out.stuck_time_s = stuck_time_s(lane);
    out.stuck_fraction = stuck_fraction_[lane];
    out.stuck = stuck(lane);
    out.events = events_[lane];
    return out;
  }
  // Whole arrays, for statistics over all lanes at once.
  const T* a_x_array() const noexcept { return state_[current_].a_x; }
  const T* stuck_fraction_array() const noexcept { return stuck_fraction_; }

  // The lane's counters (rejected inputs, event budget, state resets), kept by its oscillator.
  const Lane& lane(std::size_t index) const noexcept { return lanes_[index]; }

 private:
  // The state between steps that the common path changes, and the a_x output (while slipping
  // also the next step's a_x at the start), as arrays over the lanes. (The direction changes
  // only in redo(), so it is kept once, outside.)
  struct State {
    alignas(64) T x[N];
    alignas(64) T v[N];
    alignas(64) T a_prev[N];
    alignas(64) T a_x[N];
  };

  // Selection by bit masks on the IEEE patterns: exact for every value (signed zeros, NaN), and
  // with no condition left for the compiler to turn back into a branch.
  static Bits mask(bool condition) noexcept { return Bits(0) - static_cast<Bits>(condition); }
  static T blend(Bits when, T yes, T no) noexcept {
    Bits a, b;
    std::memcpy(&a, &yes, sizeof a);
    std::memcpy(&b, &no, sizeof b);
    const Bits mixed = (a & when) | (b & ~when);
    T out;
    std::memcpy(&out, &mixed, sizeof out);
    return out;
  }

  // Arrays <- the lane oscillator's state.
  void load(std::size_t lane) noexcept {
    const typename Lane::State s = lanes_[lane].state();
    State& now = state_[current_];
    now.x[lane] = s.x_r_m;
    now.v[lane] = s.v_r_m_per_s;
    now.a_prev[lane] = s.a_u_previous;
    direction_[lane] = s.direction;
    stuck_mask_[lane] = mask(s.direction == T(0));
    now.a_x[lane] = lanes_[lane].current().a_x_m_per_s2;
  }

  // The lane's step again, by its own oscillator, from the state before the step (still in the
  // other set of arrays), with the raw input (the oscillator replaces and counts a bad one).
  void redo(std::size_t i, T raw_input) noexcept {
    const State& before = state_[current_ ^ 1u];
    State& after = state_[current_];
    Lane& o = lanes_[i];
    // With the seat acceleration the lane kept (bit for bit what restore() would compute).
    o.restore({before.x[i], before.v[i], before.a_prev[i], direction_[i], T(0), T(0)},
              before.a_x[i]);
    const StepOutput<T> out = o.step(raw_input);
    const typename Lane::State s = o.state();
    after.x[i] = s.x_r_m;
    after.v[i] = s.v_r_m_per_s;
    after.a_prev[i] = s.a_u_previous;
    direction_[i] = s.direction;
    stuck_mask_[i] = mask(s.direction == T(0));
    after.a_x[i] = out.a_x_m_per_s2;
    friction_n_[i] = out.friction_n;
    stuck_fraction_[i] = out.stuck_fraction;
    events_[i] = out.events;
  }

  // The lanes' maps in their form: double's with the identity split off (step_map.hpp).
  using Map = typename Lane::Map;
  static constexpr bool kSplit = !std::is_same_v<Map, StepMap<T>>;
  Map lane_map(const StepMap<T>& rest, std::size_t i) const noexcept {
    if constexpr (kSplit) {
      return {rest, identity_x_[i], identity_v_[i]};
    } else {
      (void)i;
      return rest;
    }
  }

  Lane lanes_[N];
  // Coefficients (structure of arrays, copied from the lanes at configure time).
  alignas(64) T xx_[N]{}, xv_[N]{}, vx_[N]{}, vv_[N]{};
  // Double: the identity split off each lane's map; nothing for the other scalars.
  alignas(64) std::conditional_t<kSplit, T[N], T[1]> identity_x_{}, identity_v_{};
  alignas(64) T gx0_[N]{}, gx1_[N]{}, gv0_[N]{}, gv1_[N]{};
  alignas(64) T k_over_m_[N]{}, b_over_m_[N]{}, kinetic_accel_[N]{}, kinetic_n_[N]{};
  alignas(64) T static_n_[N]{};
  alignas(64) T mass_kg_[N]{}, stiffness_[N]{}, dt_s_[N]{};
  // State: two sets, read one and write the other; current_ holds the state after the last step.
  State state_[2]{};
  unsigned current_ = 0;
  alignas(64) T direction_[N]{};      // 0 stuck, +1/-1 slipping
  alignas(64) Bits stuck_mask_[N]{};  // all ones while stuck, else 0 (for blend())
  // Outputs of the last step.
  alignas(64) T friction_n_[N]{}, stuck_fraction_[N]{};
  alignas(64) T redo_[N]{};  // 1: the lane's step had an event and is redone by its oscillator
  alignas(64) std::uint8_t events_[N]{};
};

}  // namespace stickslip
