// The stick-slip observer an ECU runs: it turns the streamed cab-floor acceleration (and, where a
// sensor streams it, the measured seat acceleration) into a running picture of the seat: the model
// state (x_r, v_r, a_x, friction force, stuck), windowed statistics (RMS of a_u and a_x, T_ax, p,
// stick and slip event counts, Den Hartog's K), the friction regime with hysteresis, ISO 2631-1
// ride comfort, and from a measured seat acceleration the residual, a friction-force estimate and
// a model-mismatch flag.
//
// update() per sample: the model's step, a few multiply-adds, the comfort filters (kComfort), and
// once per completed window block (not per sample) the window figures, K and the regime (one
// square root and a few divisions). No heap; every capacity is a template parameter.
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

template <typename T, typename Law, std::size_t kWindowBlocks = 10, bool kComfort = true,
          bool kEndStops = false>
class Observer {
  using S = ScalarTraits<T>;

 public:
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
    summary_ = ObserverSummary{};
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
    ObserverSummary out = summary_;
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

  // Once per completed block.
  void refresh() noexcept {
    const WindowSums<T>& w = window_.sums();
    ObserverSummary& s = summary_;
    const double samples = double(w.samples);
    s.rms_u_m_per_s2 = samples > 0.0 ? std::sqrt(S::to_double(w.u_sq) / samples) : 0.0;
    s.rms_x_m_per_s2 = samples > 0.0 ? std::sqrt(S::to_double(w.x_sq) / samples) : 0.0;
    s.transmissibility = s.rms_u_m_per_s2 > 0.0 ? s.rms_x_m_per_s2 / s.rms_u_m_per_s2 : 0.0;
    s.stick_probability = w.steps > 0 ? S::to_double(w.stuck) / double(w.steps) : 0.0;
    s.den_hartog_k = den_hartog_factor(params_.model.kinetic_friction_n, params_.model.mass_kg,
                                       s.rms_u_m_per_s2);
    s.stick_events = w.stick_events;
    s.slip_events = w.slip_events;
    s.window_s = samples * params_.model.dt_s;
    s.window_full = window_.full();
    // Judged on full windows only: a first block or two is too short a look at the road. (No
    // friction: K = 0 says signum, or linear, suffices.)
    if (s.window_full) regime_.update(s.den_hartog_k);
    s.regime = regime_.regime();
    s.regime_known = regime_.known();
    s.regime_changes = regime_.changes();
    s.residual_rms_m_per_s2 =
        w.measured > 0 ? std::sqrt(S::to_double(w.residual_sq) / double(w.measured)) : 0.0;
    // Set above the threshold, cleared below 80 % of it (no flicker at the threshold).
    if (s.residual_rms_m_per_s2 > params_.mismatch_rms_m_per_s2) mismatch_ = true;
    if (s.residual_rms_m_per_s2 < 0.8 * params_.mismatch_rms_m_per_s2) mismatch_ = false;
    s.model_mismatch = mismatch_;
  }

  Model model_;
  BlockWindow<T, kWindowBlocks> window_;
  ExponentialWindow<T> exponential_;
  RegimeTracker regime_;
  RideComfort<T> comfort_;
  ObserverParams params_{};
  ObserverEstimate<T> estimate_{};
  ObserverSummary summary_{};
  T mass_kg_{}, stiffness_{}, damping_{};
  bool was_stuck_ = false;
  bool mismatch_ = false;
  std::uint64_t samples_ = 0;
};

}  // namespace stickslip
