// The stick-slip observer an ECU runs: it turns the streamed cab-floor acceleration (and, where a
// sensor streams it, the measured seat acceleration) into a running picture of the seat: the model
// state (x_r, v_r, a_x, friction force, stuck), windowed statistics (RMS of a_u and a_x, T_ax, p,
// stick and slip event counts, Den Hartog's K), the friction regime with hysteresis, ISO 2631-1
// ride comfort, and from a measured seat acceleration the residual, a friction-force estimate and
// a model-mismatch flag.
//
// update() per sample: the model's step, a few multiply-adds, the comfort filters (kComfort), and
// once per completed window block (not per sample) the window figures, K and the regime (a few
// square roots and divisions, in the scalar itself for float and double: a float observer does
// no double arithmetic). No heap; every capacity is a template parameter.
//
// kEndStops: the model is the seat with end stops (EndStopOscillator, models/end_stops.hpp;
// ObserverParams::stops, laws NoFriction and CoulombStickSlip, double or float), whose step is
// then the estimate, and the measured friction also takes off the stop's force.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "stickslip/core/params.hpp"
#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/ride_comfort.hpp"
#include "stickslip/models/end_stops.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/observer/regime_tracker.hpp"
#include "stickslip/observer/window_statistics.hpp"

namespace stickslip {

struct ObserverParams {
  OscillatorParams model;
  EndStopParams stops;     // the stops, for an observer of the seat with end stops (kEndStops)
  double window_s = 10.0;  // block window length (split into the kWindowBlocks blocks)
  double exponential_time_s = 10.0;   // tau of the exponential window
  double regime_hysteresis_k = 0.05;  // K margin beyond a regime boundary before the regime changes
  double mismatch_rms_m_per_s2 = 0.1;  // residual RMS (window) above which the model is flagged
  ComfortWeighting weighting = ComfortWeighting::wk;  // the seat's vertical axis
};

// Per-sample estimate.
template <typename T>
struct ObserverEstimate {
  StepOutput<T> model{};    // the model's step (x_r, v_r, a_x, f_f, stuck, ...)
  bool measured = false;    // a measured seat acceleration came with this sample
  T residual_m_per_s2{};    // a_x,measured - a_x,model (0 when not measured)
  T measured_friction_n{};  // F_f from the measurement: -m a_x,meas - k x_r - b v_r (- F_stop)
};

// Window figures, refreshed when a block completes (and on demand by summary()). The regime is
// judged once the window is full.
struct ObserverSummary {
  double rms_u_m_per_s2 = 0.0, rms_x_m_per_s2 = 0.0, transmissibility = 0.0;
  double stick_probability = 0.0, den_hartog_k = 0.0;
  std::uint32_t stick_events = 0, slip_events = 0;
  double window_s = 0.0;  // the time the window figures cover so far
  bool window_full = false;
  double exp_rms_u_m_per_s2 = 0.0, exp_rms_x_m_per_s2 = 0.0, exp_transmissibility = 0.0;
  double exp_stick_probability = 0.0, exp_den_hartog_k = 0.0;
  FrictionRegime regime = FrictionRegime::signum_suffices;
  bool regime_known = false;
  std::uint32_t regime_changes = 0;
  double residual_rms_m_per_s2 = 0.0;  // over the window's measured samples
  bool model_mismatch = false;
};

// The block window's figures as of its last completed block, in the observer's figure type R.
template <typename R>
struct WindowFigures {
  R rms_u_m_per_s2{}, rms_x_m_per_s2{}, transmissibility{}, stick_probability{}, den_hartog_k{};
  R residual_rms_m_per_s2{};  // over the window's measured samples
  std::uint32_t samples = 0;  // the samples the figures cover (0: no block completed yet)
  std::uint32_t stick_events = 0, slip_events = 0;
};

template <typename T, typename Law, std::size_t kWindowBlocks = 10, bool kComfort = true,
          bool kEndStops = false>
class Observer {
  using S = ScalarTraits<T>;

 public:
  // The window figures' type: the scalar itself where it is floating point (float on an FPU
  // without double: no software double once per block), double for fixed point.
  using Figure = std::conditional_t<std::is_floating_point_v<T>, T, double>;

  using Model = std::conditional_t<kEndStops, EndStopOscillator<T, Law>, Oscillator<T, Law>>;

  ConfigResult configure(const ObserverParams& params) noexcept {
    ConfigResult result;
    if constexpr (kEndStops) {
      result = model_.configure(params.model, params.stops);
    } else {
      result = model_.configure(params.model);
    }
    if (!result.ok()) return result;
    const double dt = params.model.dt_s;
    const auto refuse = [&result](Status status, const char* name, double value, const char* why) {
      result = refusal(status);
      result.message.append(name).append(" = ").append(value).append(why);
      return result;
    };
    if (!std::isfinite(params.window_s) || !(params.window_s >= dt * double(kWindowBlocks))) {
      return refuse(Status::out_of_range, "window_s", params.window_s,
                    " must be finite and hold at least one sample per window block");
    }
    if (!(params.window_s / dt <= 4.0e9)) {
      return refuse(Status::out_of_range, "window_s", params.window_s, " exceeds 4e9 samples");
    }
    if (!std::isfinite(params.exponential_time_s) || !(params.exponential_time_s >= dt)) {
      return refuse(Status::out_of_range, "exponential_time_s", params.exponential_time_s,
                    " must be finite and at least one sample interval");
    }
    if (!(params.regime_hysteresis_k >= 0.0 && params.regime_hysteresis_k < 0.175)) {
      return refuse(Status::out_of_range, "regime_hysteresis_k", params.regime_hysteresis_k,
                    " must be in [0, 0.175) (half the gap between K = 0.4 and 0.75)");
    }
    if (!(params.mismatch_rms_m_per_s2 > 0.0) || !std::isfinite(params.mismatch_rms_m_per_s2)) {
      return refuse(Status::out_of_range, "mismatch_rms_m_per_s2", params.mismatch_rms_m_per_s2,
                    " must be finite and > 0");
    }
    if constexpr (kComfort) {
      const ConfigResult comfort = comfort_.configure(params.weighting, 1.0 / dt);
      if (!comfort.ok()) return comfort;
    }
    const double per_block = std::round(params.window_s / (dt * double(kWindowBlocks)));
    window_.configure(static_cast<std::uint32_t>(per_block));
    exponential_.configure(S::from_double(-std::expm1(-dt / params.exponential_time_s)));
    regime_.configure(params.regime_hysteresis_k);
    params_ = params;
    kinetic_friction_ = Figure(params.model.kinetic_friction_n);
    mass_ = Figure(params.model.mass_kg);
    mismatch_set_ = Figure(params.mismatch_rms_m_per_s2);
    mismatch_clear_ = Figure(0.8 * params.mismatch_rms_m_per_s2);
    mass_kg_ = S::from_double(params.model.mass_kg);
    stiffness_ = S::from_double(params.model.stiffness_n_per_m);
    damping_ = S::from_double(params.model.damping_ns_per_m);
    reset(T(0));
    return result;
  }

  // Rest (or the given state) with the first input sample a_u0; clears every statistic.
  void reset(T a_u0, T x0_m = T(0), T v0_m_per_s = T(0)) noexcept {
    model_.reset(x0_m, v0_m_per_s, a_u0);
    window_.reset();
    exponential_.reset();
    regime_.reset();
    if constexpr (kComfort) comfort_.reset();
    estimate_ = ObserverEstimate<T>{};
    estimate_.model = model_.current();
    was_stuck_ = estimate_.model.stuck;
    // Ride comfort covers every sample of the stream, the first one too (the windows count steps).
    if constexpr (kComfort) comfort_.add_sample(a_u0, estimate_.model.a_x_m_per_s2);
    mismatch_ = false;
    samples_ = 0;
    completed_blocks_ = 0;
    figures_ = WindowFigures<Figure>{};
  }

  // One floor sample (m/s^2).
  const ObserverEstimate<T>& update(T a_u) noexcept { return advance(a_u, false, T(0)); }
  // One floor sample and the measured seat acceleration of the same instant.
  const ObserverEstimate<T>& update(T a_u, T a_x_measured) noexcept {
    return advance(a_u, S::is_finite(a_x_measured), a_x_measured);
  }

  const ObserverEstimate<T>& estimate() const noexcept { return estimate_; }
  // The figures as of the last completed block, with the exponential window's as of now.
  ObserverSummary summary() const noexcept {
    const WindowFigures<Figure>& f = figures_;
    ObserverSummary out;
    out.rms_u_m_per_s2 = double(f.rms_u_m_per_s2);
    out.rms_x_m_per_s2 = double(f.rms_x_m_per_s2);
    out.transmissibility = double(f.transmissibility);
    out.stick_probability = double(f.stick_probability);
    out.den_hartog_k = double(f.den_hartog_k);
    out.stick_events = f.stick_events;
    out.slip_events = f.slip_events;
    out.window_s = double(f.samples) * params_.model.dt_s;
    out.window_full = window_.full();
    out.regime = regime_.regime();
    out.regime_known = regime_.known();
    out.regime_changes = regime_.changes();
    out.residual_rms_m_per_s2 = double(f.residual_rms_m_per_s2);
    out.model_mismatch = mismatch_;
    const double u = std::sqrt(S::to_double(exponential_.mean_u_sq()));
    const double x = std::sqrt(S::to_double(exponential_.mean_x_sq()));
    out.exp_rms_u_m_per_s2 = u;
    out.exp_rms_x_m_per_s2 = x;
    out.exp_transmissibility = u > 0.0 ? x / u : 0.0;
    out.exp_stick_probability = S::to_double(exponential_.stuck_share());
    out.exp_den_hartog_k =
        den_hartog_factor(params_.model.kinetic_friction_n, params_.model.mass_kg, u);
    return out;
  }
  // The block window's figures as of the last completed block, as computed (summary() has them in
  // double with the exponential window's).
  const WindowFigures<Figure>& window() const noexcept { return figures_; }
  // Blocks completed since reset(): the window figures change exactly when this does.
  std::uint64_t completed_blocks() const noexcept { return completed_blocks_; }
  FrictionRegime regime() const noexcept { return regime_.regime(); }
  bool model_mismatch() const noexcept { return mismatch_; }
  std::uint64_t samples() const noexcept { return samples_; }
  const Model& model() const noexcept { return model_; }
  const RideComfort<T>& comfort() const noexcept { return comfort_; }

 private:
  const ObserverEstimate<T>& advance(T a_u, bool measured, T a_x_measured) noexcept {
    const StepOutput<T> out = model_.step(a_u);
    estimate_.model = out;
    estimate_.measured = measured;
    const T residual = measured ? a_x_measured - out.a_x_m_per_s2 : T(0);
    estimate_.residual_m_per_s2 = residual;
    estimate_.measured_friction_n =
        measured ? -(mass_kg_ * a_x_measured + stiffness_ * out.x_r_m + damping_ * out.v_r_m_per_s)
                 : T(0);
    if constexpr (kEndStops) {
      if (measured) estimate_.measured_friction_n -= model_.stop_force_n();
    }
    const bool stick_event = out.stuck && !was_stuck_;
    const bool slip_event = !out.stuck && was_stuck_;
    was_stuck_ = out.stuck;
    ++samples_;
    exponential_.add(a_u, out.a_x_m_per_s2, out.stuck_fraction, residual);
    if constexpr (kComfort) comfort_.add_sample(a_u, out.a_x_m_per_s2);
    if (window_.add(a_u, out.a_x_m_per_s2, out.stuck_fraction, true, measured, residual,
                    stick_event, slip_event)) {
      refresh();
    }
    return estimate_;
  }

  // Once per completed block, in Figure.
  void refresh() noexcept {
    ++completed_blocks_;
    const WindowSums<T>& w = window_.sums();
    WindowFigures<Figure>& f = figures_;
    const Figure samples = Figure(w.samples);
    f.rms_u_m_per_s2 = samples > Figure(0) ? std::sqrt(figure(w.u_sq) / samples) : Figure(0);
    f.rms_x_m_per_s2 = samples > Figure(0) ? std::sqrt(figure(w.x_sq) / samples) : Figure(0);
    f.transmissibility =
        f.rms_u_m_per_s2 > Figure(0) ? f.rms_x_m_per_s2 / f.rms_u_m_per_s2 : Figure(0);
    f.stick_probability = w.steps > 0 ? figure(w.stuck) / Figure(w.steps) : Figure(0);
    f.den_hartog_k = den_hartog_factor_in(kinetic_friction_, mass_, f.rms_u_m_per_s2);
    f.samples = w.samples;
    f.stick_events = w.stick_events;
    f.slip_events = w.slip_events;
    // Judged on full windows only: a first block or two is too short a look at the road. (No
    // friction: K = 0 says signum, or linear, suffices.)
    if (window_.full()) regime_.update(f.den_hartog_k);
    f.residual_rms_m_per_s2 =
        w.measured > 0 ? std::sqrt(figure(w.residual_sq) / Figure(w.measured)) : Figure(0);
    // Set above the threshold, cleared below 80 % of it (no flicker at the threshold).
    if (f.residual_rms_m_per_s2 > mismatch_set_) mismatch_ = true;
    if (f.residual_rms_m_per_s2 < mismatch_clear_) mismatch_ = false;
  }

  static Figure figure(T value) noexcept {
    if constexpr (std::is_floating_point_v<T>) {
      return value;
    } else {
      return S::to_double(value);
    }
  }

  Model model_;
  BlockWindow<T, kWindowBlocks> window_;
  ExponentialWindow<T> exponential_;
  RegimeTracker regime_;
  RideComfort<T> comfort_;
  ObserverParams params_{};
  ObserverEstimate<T> estimate_{};
  WindowFigures<Figure> figures_{};
  T mass_kg_{}, stiffness_{}, damping_{};
  Figure kinetic_friction_{}, mass_{}, mismatch_set_{}, mismatch_clear_{};
  bool was_stuck_ = false;
  bool mismatch_ = false;
  std::uint64_t samples_ = 0;
  std::uint64_t completed_blocks_ = 0;
};

}  // namespace stickslip
