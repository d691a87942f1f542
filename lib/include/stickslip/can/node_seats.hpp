// The seats lib/ offers the ECU node (ecu_node.hpp): a model behind the node's word interface.
// a_u arrives as the SeatInput word (2^-10 m/s^2 per bit); the outputs leave as the
// SeatMotion/SeatForce words, the window figures as the SeatStats/SeatScene words.
//   OscillatorSeat<T, Law>: float or double; decode and encode are exact (power-of-two scales),
//                           so the words equal the host's double path for the same outputs. No
//                           running statistics (StatsWords says not available).
//   ObserverSeat<T, Law>:   float or double: the observer (observer/observer.hpp), whose estimate
//                           is the oscillator's step bit for bit, and its block window's T_ax, p
//                           and K, as the host node publishes them (stats_words()); with a third
//                           parameter true, of the seat with end stops (ObserverParams::stops).
//   ScaledSeat<T, Law>:     a 32-bit fixed-point scalar in scene units (models/
//                           scaled_oscillator.hpp, the Cortex-M0+ build): one integer product and
//                           a rounding shift per signal (CountScale), no float in the step; T_ax,
//                           p and K from the block window over its own words (word_window.hpp).
//                           Its third parameter may be another model in scene units with the
//                           same interface: ScaledEndStopOscillator (models/scaled_end_stops.hpp),
//                           configured with the stops too (the host node's seat with end stops).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "stickslip/can/codec.hpp"
#include "stickslip/can/ecu_node.hpp"
#include "stickslip/can/word_window.hpp"
#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/models/scaled_oscillator.hpp"
#include "stickslip/observer/observer.hpp"

namespace stickslip::can {

namespace seat_detail {

// Exact: a_u is the word times 2^-10 (a power of two: a multiply, no ldexp call).
template <typename T>
T input(std::uint16_t word) noexcept {
  return T(word_as_signed(word)) * (T(1) / T(1u << kSeatInput.signals[0].fraction_bits));
}

// quantise() (codec.hpp) for a signed signal, with the scale a compile-time power of two: the
// same word and saturation flag (the scaling is exact either way), without its ldexp calls.
static_assert(kSeatMotion.signals[0].is_signed && kSeatMotion.signals[1].is_signed &&
                  kSeatForce.signals[0].is_signed && kSeatForce.signals[1].is_signed,
              "word() encodes signed signals");
template <int kFractionBits, typename T>
Quantised word(T value) noexcept {
  if (value != value) return {signed_word(kSignedNotAvailable), false};
  const T scaled = value * T(1u << kFractionBits);  // exact
  const T limit = T(kSignedMax) + T(0.5);
  if (scaled >= limit) return {signed_word(kSignedMax), true};
  if (scaled <= -limit) return {signed_word(-kSignedMax), true};
  return {signed_word(static_cast<std::int16_t>(std::round(scaled))), false};
}

template <typename T>
SeatWords words(const StepOutput<T>& out) noexcept {
  SeatWords w;
  w.a_x = word<kSeatMotion.signals[0].fraction_bits>(out.a_x_m_per_s2);
  w.x_r = word<kSeatMotion.signals[1].fraction_bits>(out.x_r_m);
  w.v_r = word<kSeatForce.signals[0].fraction_bits>(out.v_r_m_per_s);
  w.f_f = word<kSeatForce.signals[1].fraction_bits>(out.friction_n);
  w.stuck = out.stuck;
  return w;
}

}  // namespace seat_detail

template <typename T, typename Law>
class OscillatorSeat {
 public:
  using Scalar = T;

  // The model's parameters (dt_s = the sample interval of the stream) and where it starts.
  ConfigResult configure(const OscillatorParams& params, T x0_m = T(0),
                         T v0_m_per_s = T(0)) noexcept {
    x0_ = x0_m;
    v0_ = v0_m_per_s;
    return oscillator_.configure(params);
  }

  SeatWords start(std::uint16_t a_u_word) noexcept {
    oscillator_.reset(x0_, v0_, input(a_u_word));
    last_ = oscillator_.current();
    return last_words();
  }
  SeatWords step(std::uint16_t a_u_word) noexcept {
    advance(input(a_u_word));
    return finish_step(a_u_word);
  }
  // The parts of step(), for a caller that puts the model's step in a function of its own (the
  // firmware: its step budget is measured from there): the input, the step, the words.
  STICKSLIP_INLINE_STEP void advance(T a_u) noexcept {
    oscillator_.step(a_u, last_);  // in place: no copy on an interrupt's stack
  }
  SeatWords finish_step(std::uint16_t /*a_u_word*/) const noexcept { return last_words(); }
  StatsWords statistics() const noexcept { return {}; }

  static T input(std::uint16_t word) noexcept { return seat_detail::input<T>(word); }
  SeatWords last_words() const noexcept { return seat_detail::words(last_); }

  const StepOutput<T>& last() const noexcept { return last_; }
  const Oscillator<T, Law>& oscillator() const noexcept { return oscillator_; }

 private:
  Oscillator<T, Law> oscillator_;
  StepOutput<T> last_{};
  T x0_ = T(0), v0_ = T(0);
};

// The node's observer window: ten blocks of a tenth of ObserverParams::window_s each.
inline constexpr std::size_t kSeatWindowBlocks = 10;

// The observer a node runs for the seat `model`: a 10 s window (or ten samples, if dt_s is over
// a second) and a 10 s exponential window.
inline ObserverParams seat_observer_params(const OscillatorParams& model) noexcept {
  ObserverParams params;
  params.model = model;
  params.window_s = std::fmax(10.0, 10.0 * model.dt_s);
  params.exponential_time_s = std::fmax(10.0, model.dt_s);
  return params;
}

// kEndStops: the observer of the seat with end stops (ObserverParams::stops).
template <typename T, typename Law, bool kEndStops = false>
class ObserverSeat {
 public:
  using Scalar = T;
  // Ride comfort is not published on the bus: the seat's observer has no comfort filters (the
  // window figures do not depend on them).
  using Model = Observer<T, Law, kSeatWindowBlocks, false, kEndStops>;

  // The observer's parameters (model.dt_s = the sample interval of the stream); the seat starts
  // at rest.
  ConfigResult configure(const ObserverParams& params) noexcept {
    return observer_.configure(params);
  }

  SeatWords start(std::uint16_t a_u_word) noexcept {
    observer_.reset(input(a_u_word));
    note_window();
    return last_words();
  }
  SeatWords step(std::uint16_t a_u_word) noexcept {
    advance(input(a_u_word));
    return finish_step(a_u_word);
  }
  // The parts of step(), for a caller that puts the seat's step in a function of its own (the
  // firmware): the input, the observer's update, the words. The statistics words are quantised
  // here when a block completes (once per block, not per call of statistics()).
  STICKSLIP_INLINE_STEP void advance(T a_u) noexcept {
    observer_.update(a_u);
    if (observer_.completed_blocks() != blocks_) note_window();
  }
  SeatWords finish_step(std::uint16_t /*a_u_word*/) const noexcept { return last_words(); }
  StatsWords statistics() const noexcept { return stats_; }

  static T input(std::uint16_t word) noexcept { return seat_detail::input<T>(word); }
  SeatWords last_words() const noexcept { return seat_detail::words(last()); }

  const StepOutput<T>& last() const noexcept { return observer_.estimate().model; }
  const Model& observer() const noexcept { return observer_; }
  const typename Model::Model& oscillator() const noexcept { return observer_.model(); }

 private:
  void note_window() noexcept {
    blocks_ = observer_.completed_blocks();
    const auto& window = observer_.window();
    stats_ = stats_words(window.samples > 0, window.transmissibility, window.stick_probability,
                         window.den_hartog_k);
  }

  Model observer_;
  StatsWords stats_;
  std::uint64_t blocks_ = 0;
};

template <typename T, typename Law, typename Model = ScaledOscillator<T, Law>>
class ScaledSeat {
 public:
  using Scalar = T;

  // Configures the scaled model (it starts at rest; `more`: what else its configure() takes, the
  // stops of ScaledEndStopOscillator) and the word scales of its scene units. Refuses
  // (out_of_range, naming the signal) a scene whose units no CountScale can carry.
  template <typename... More>
  ConfigResult configure(const OscillatorParams& si, const More&... more) noexcept {
    ConfigResult result = model_.configure(si, more...);
    if (!result.ok()) return result;
    const SceneUnits& u = model_.units();
    const auto per_bit = [](const SignalSpec& s) { return std::ldexp(1.0, -s.fraction_bits); };
    const char* failed = nullptr;
    if (!input_.set_count_to_scalar(per_bit(kSeatInput.signals[0]) / u.acceleration_m_per_s2()))
      failed = "SeatInput.a_u";
    else if (!a_x_.set_scalar_to_count(u.acceleration_m_per_s2() / per_bit(kSeatMotion.signals[0])))
      failed = "SeatMotion.a_x";
    else if (!x_r_.set_scalar_to_count(u.length_m / per_bit(kSeatMotion.signals[1])))
      failed = "SeatMotion.x_r";
    else if (!v_r_.set_scalar_to_count(u.velocity_m_per_s() / per_bit(kSeatForce.signals[0])))
      failed = "SeatForce.v_r";
    else if (!f_f_.set_scalar_to_count(u.force_n() / per_bit(kSeatForce.signals[1])))
      failed = "SeatForce.f_f";
    if (failed == nullptr) {
      // The observer's block length for this seat (Observer::configure()'s rule).
      const double per_block =
          std::round(seat_observer_params(si).window_s / (si.dt_s * double(kSeatWindowBlocks)));
      if (!(per_block * double(kSeatWindowBlocks) <= 4.0e9)) {
        result = refusal(Status::out_of_range);
        result.message
            .append("dt_s: the statistics window (10 s) would hold over 4e9 samples, got ")
            .append(si.dt_s)
            .append(" s");
        return result;
      }
      window_.configure(static_cast<std::uint32_t>(per_block), si.kinetic_friction_n, si.mass_kg);
      return result;
    }
    result = refusal(Status::out_of_range);
    result.message.append(failed)
        .append(": the scene unit is out of the word scale's reach (length L = ")
        .append(u.length_m)
        .append(" m)");
    return result;
  }

  SeatWords start(std::uint16_t a_u_word) noexcept {
    model_.oscillator().reset(T(0), T(0), input(a_u_word));
    last_ = model_.oscillator().current();
    window_.reset();  // as the observer's: the steps after the first sample
    return words(last_);
  }
  SeatWords step(std::uint16_t a_u_word) noexcept {
    advance(input(a_u_word));
    return finish_step(a_u_word);
  }
  // The parts of step(), for a caller that puts the model's step in a function of its own (the
  // firmware: its step budget is measured from there): the input, the step, then the words, which
  // also go into the statistics window (outside the step's budget).
  STICKSLIP_INLINE_STEP void advance(T a_u_scaled) noexcept {
    model_.step(a_u_scaled, last_);  // in place: no copy on an interrupt's stack
  }
  SeatWords finish_step(std::uint16_t a_u_word) noexcept {
    const SeatWords w = words(last_);
    const std::int32_t stuck = last_.stuck_fraction.raw();  // Q.24 in [0, 1]
    static_assert(T::kFractionBits == 24, "the window takes the stuck fraction in Q.24");
    window_.add(word_as_signed(a_u_word), word_as_signed(w.a_x.word),
                stuck > 0 ? static_cast<std::uint32_t>(stuck) : 0u);
    return w;
  }
  // T_ax, p and K of the window over this seat's words, as of its last published block.
  StatsWords statistics() const noexcept { return window_.words(); }

  T input(std::uint16_t word) const noexcept { return input_.to_scalar(word_as_signed(word)); }
  SeatWords last_words() const noexcept { return words(last_); }

  const StepOutput<T>& last() const noexcept { return last_; }
  const Model& model() const noexcept { return model_; }

 private:
  static constexpr std::int32_t kSignedLimit = kSignedMax;

  // Rounded to nearest as quantise() does; beyond +-32767 clipped and flagged.
  static Quantised word(const CountScale<T>& scale, T value) noexcept {
    const std::int32_t count = scale.to_count(value, kSignedLimit + 1);
    if (count > kSignedLimit) return {signed_word(kSignedMax), true};
    if (count < -kSignedLimit) return {signed_word(-kSignedMax), true};
    return {signed_word(static_cast<std::int16_t>(count)), false};
  }
  SeatWords words(const StepOutput<T>& out) const noexcept {
    SeatWords w;
    w.a_x = word(a_x_, out.a_x_m_per_s2);
    w.x_r = word(x_r_, out.x_r_m);
    w.v_r = word(v_r_, out.v_r_m_per_s);
    w.f_f = word(f_f_, out.friction_n);
    w.stuck = out.stuck;
    return w;
  }

  Model model_;
  StepOutput<T> last_{};
  CountScale<T> input_, a_x_, x_r_, v_r_, f_f_;
  WordWindow<kSeatWindowBlocks> window_;
};

}  // namespace stickslip::can
