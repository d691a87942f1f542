// State and friction estimator for a stick-slip seat that corrects itself with the ECU's sensors:
// per sample the cab-floor acceleration a_u and, where the sensors deliver them, the measured seat
// acceleration a_x and the measured travel x_r. Outputs x_r, v_r, the friction force F_f, the
// stuck state, and online estimates of F_fk and F_fs.
//
// Method: a mode-aware Kalman filter. The plant is two different linear systems glued at events,
// so the filter runs the one the seat is in and re-initialises at the events:
//   - slipping: state [x_r, v_r, F_f] with F_f a random walk (it is F_fk sgn(v_r): constant within
//     a slip phase, drifting slowly), propagated by the exact step of
//       m dv_r/dt + b v_r + k x_r + F_f = -m a_u        (a_u first-order hold, F_f held)
//     and corrected by a_x = -(k x_r + b v_r + F_f)/m and by x_r. At a reversal (the predicted v_r
//     crosses zero) F_f changes sign, as the Coulomb law says, instead of being left for the
//     random walk to discover (a jump of 2 F_fk would need a process noise that spoils every other
//     sample). Near v_r = 0 an a_x innovation beyond a gate is an event the prediction missed: a
//     stick if the measured relative acceleration vanished, else a reversal.
//   - stuck: v_r = 0, x_r constant (corrected by the travel sensor), F_f = -(k x_r + m a_u), the
//     holding force. Here a_x - a_u is pure sensor error, so its mean is the accelerometers'
//     relative bias, learnt while stuck and removed from a_x while slipping.
// Why model-based and not just integrate a_x - a_u: while slipping the model predicts the
// acceleration to the accuracy of F_fk (about 1 N, 0.01 m/s^2), better than one accelerometer
// sample (0.02 m/s^2 each for a_x and a_u), so v_r comes out less noisy than from kinematics
// alone (docs/IDENTIFICATION.md); and without a travel sensor x_r stays observable through the
// friction law: within a slip phase only k x_r + F_f is seen, but F_f flips at each reversal while
// x_r does not.
// The stuck state is decided from the measurements, never from the F_fs estimate (which is the
// thing being learnt): stuck when |v_r| and the low-passed relative acceleration a_x - a_u are both
// small; slipping again when a_x - a_u, integrated since the stick with a leak that bounds the
// noise's random walk, leaves its band (without a_x: when the load exceeds the F_fs estimate).
// Friction learning: slipping with |v_r| clear of zero, F_f sgn(v_r) is a sample of F_fk, averaged
// exponentially over kinetic_friction_time_s of slip time; at each break-away the largest holding
// force of the stuck phase is a sample of F_fs. Both estimates hold while no samples come.
// Without a travel sensor a weak prior x_r ~ N(0, (F_fs/k)^2) while stuck (the spring centres the
// seat to within the stick band) bounds x_r where the reversals are too rare to pin it.
// Cost per sample: a 3x3 covariance propagation and up to two scalar updates. The only divisions
// are 1/S of those updates: the filter is time-varying on purpose (the mode and the measurements
// present change from sample to sample, and the covariance must follow), so its gains cannot be
// precomputed. No transcendental call in step(). Float and double from this one source; fixed
// point is not offered: the covariance spans 1e-16 .. 1e2 in SI units, which no Q format holds.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "stickslip/core/scalar.hpp"
#include "stickslip/core/status.hpp"
#include "stickslip/integrators/discretisation.hpp"
#include "stickslip/integrators/step_map.hpp"
#include "stickslip/observer/state_estimator_params.hpp"

namespace stickslip {

template <typename T>
struct StateEstimate {
  T x_r_m{};
  T v_r_m_per_s{};
  T friction_n{};                      // F_f on the seat (the holding force while stuck)
  T kinetic_friction_n{};              // F_fk estimate
  T static_friction_n{};               // F_fs estimate
  T bias_m_per_s2{};                   // bias of a_x - a_u (learnt while stuck)
  T relative_acceleration_m_per_s2{};  // low-passed a_x - a_u - bias (the model's without a_x)
  bool stuck = true;
  std::uint32_t breakaways = 0;       // break-aways seen (F_fs samples taken)
  std::uint64_t kinetic_samples = 0;  // F_fk samples taken (slip samples with a_x)
};

template <typename T>
class StateEstimator {
  using S = ScalarTraits<T>;

 public:
  ConfigResult configure(const StateEstimatorParams& p) noexcept {
    ConfigResult result = validate(p);
    if (!result.ok()) return result;
    precompute(p);
    configured_ = true;
    reset(T(0));
    return result;
  }

 private:
  // Every refusal of configure(), naming the parameter.
  static ConfigResult validate(const StateEstimatorParams& p) noexcept {
    ConfigResult result;
    const auto refuse = [&result](const char* name, double value, const char* why) {
      result.status = std::isfinite(value) ? Status::out_of_range : Status::not_finite;
      result.message.clear();
      result.message.append(name).append(" = ").append(value).append(why);
      return result;
    };
    struct Named {
      const char* name;
      double value;
    };
    const Named positive[] = {
        {"mass_kg", p.mass_kg},
        {"stiffness_n_per_m", p.stiffness_n_per_m},
        {"dt_s", p.dt_s},
        {"seat_acceleration_noise_m_per_s2", p.seat_acceleration_noise_m_per_s2},
        {"model_force_noise_n", p.model_force_noise_n},
        {"breakaway_friction_uncertainty_n", p.breakaway_friction_uncertainty_n},
        {"kinetic_friction_time_s", p.kinetic_friction_time_s},
        {"bias_time_s", p.bias_time_s},
        {"stick_velocity_m_per_s", p.stick_velocity_m_per_s},
        {"stick_acceleration_m_per_s2", p.stick_acceleration_m_per_s2},
        {"acceleration_filter_time_s", p.acceleration_filter_time_s},
        {"breakaway_velocity_m_per_s", p.breakaway_velocity_m_per_s},
        {"breakaway_leak_time_s", p.breakaway_leak_time_s},
        {"slip_confidence_m_per_s", p.slip_confidence_m_per_s},
        {"event_velocity_m_per_s", p.event_velocity_m_per_s},
        {"event_gate_sigma", p.event_gate_sigma},
    };
    for (const Named& q : positive) {
      if (!std::isfinite(q.value) || !(q.value > 0.0)) {
        return refuse(q.name, q.value, " must be finite and > 0");
      }
    }
    const Named non_negative[] = {
        {"damping_ns_per_m", p.damping_ns_per_m},
        {"initial_kinetic_friction_n", p.initial_kinetic_friction_n},
        {"floor_acceleration_noise_m_per_s2", p.floor_acceleration_noise_m_per_s2},
        {"travel_noise_m", p.travel_noise_m},
        {"travel_resolution_m", p.travel_resolution_m},
        {"friction_walk_n_per_sqrt_s", p.friction_walk_n_per_sqrt_s},
    };
    for (const Named& q : non_negative) {
      if (!std::isfinite(q.value) || !(q.value >= 0.0)) {
        return refuse(q.name, q.value, " must be finite and >= 0");
      }
    }
    if (!(p.travel_noise_m > 0.0 || p.travel_resolution_m > 0.0)) {
      // A travel update with zero variance on a travel the filter is sure of divides by zero.
      return refuse("travel_noise_m", p.travel_noise_m,
                    " and travel_resolution_m must not both be 0");
    }
    if (!std::isfinite(p.initial_static_friction_n) ||
        !(p.initial_static_friction_n >= p.initial_kinetic_friction_n)) {
      return refuse("initial_static_friction_n", p.initial_static_friction_n,
                    " must be finite and >= initial_kinetic_friction_n");
    }
    if (!(p.static_friction_weight > 0.0 && p.static_friction_weight <= 1.0)) {
      return refuse("static_friction_weight", p.static_friction_weight, " must be in (0, 1]");
    }
    const double dt = p.dt_s;
    const Named time_constants[] = {
        {"kinetic_friction_time_s", p.kinetic_friction_time_s},
        {"acceleration_filter_time_s", p.acceleration_filter_time_s},
        {"breakaway_leak_time_s", p.breakaway_leak_time_s},
        {"bias_time_s", p.bias_time_s},
    };
    for (const Named& q : time_constants) {
      if (!(q.value >= dt)) {  // an average, filter or leak shorter than the step cannot act
        refuse("dt_s", dt, " exceeds ");
        result.message.append(q.name).append(" = ").append(q.value);
        return result;
      }
    }
    // One reversal per step at most (the sign test on the predicted v_r).
    const double omega0 = std::sqrt(p.stiffness_n_per_m / p.mass_kg);
    if (!(omega0 * dt <= 0.5)) {
      return refuse("dt_s", dt, " must satisfy sqrt(k/m) dt <= 0.5");
    }
    return result;
  }

  // Every coefficient step() uses, from validated params.
  void precompute(const StateEstimatorParams& p) noexcept {
    const double dt = p.dt_s;
    const double m = p.mass_kg;
    const StepMap<double> map =
        linear_step_map(Integrator::exact, p.stiffness_n_per_m / m, p.damping_ns_per_m / m, dt);
    map_ = StepMap<T>::from_double(map);
    // F_f enters the map's input g = -(a_u + F_f/m) at both ends of the step.
    c_.x_friction = S::from_double(-(map.gx0 + map.gx1) / m);
    c_.v_friction = S::from_double(-(map.gv0 + map.gv1) / m);
    // Process noise: the floor sensor's noise and the unknown force act as accelerations held
    // over the step; the friction walks.
    const double a_var = p.floor_acceleration_noise_m_per_s2 * p.floor_acceleration_noise_m_per_s2 +
                         (p.model_force_noise_n / m) * (p.model_force_noise_n / m);
    const double a_var_sensors =
        p.floor_acceleration_noise_m_per_s2 * p.floor_acceleration_noise_m_per_s2 +
        p.seat_acceleration_noise_m_per_s2 * p.seat_acceleration_noise_m_per_s2;
    const double gx = 0.5 * dt * dt, gv = dt;
    c_.q.xx = S::from_double(a_var * gx * gx);
    c_.q.xv = S::from_double(a_var * gx * gv);
    c_.q.vv = S::from_double(a_var * gv * gv);
    c_.q.xf = S::from_double(0.0);
    c_.q.vf = S::from_double(0.0);
    c_.q.ff = S::from_double(p.friction_walk_n_per_sqrt_s * p.friction_walk_n_per_sqrt_s * dt);
    c_.q_stuck_xx = c_.q.xx;
    c_.r_accel =
        S::from_double(p.seat_acceleration_noise_m_per_s2 * p.seat_acceleration_noise_m_per_s2);
    c_.r_travel = S::from_double(p.travel_noise_m * p.travel_noise_m +
                                 p.travel_resolution_m * p.travel_resolution_m / 12.0);
    c_.h_x = S::from_double(-p.stiffness_n_per_m / m);
    c_.h_v = S::from_double(-p.damping_ns_per_m / m);
    c_.h_f = S::from_double(-1.0 / m);
    c_.mass = S::from_double(m);
    c_.stiffness = S::from_double(p.stiffness_n_per_m);
    c_.damping = S::from_double(p.damping_ns_per_m);
    c_.inv_stiffness = S::from_double(1.0 / p.stiffness_n_per_m);
    c_.inv_mass = S::from_double(1.0 / m);
    c_.dt = S::from_double(dt);
    c_.half_dt = S::from_double(0.5 * dt);
    // One sample's force balance: m a_x with both accelerometers' noise, doubled for the slip
    // that has already built up until the detection.
    c_.breakaway_balance_var = S::from_double(4.0 * m * m * a_var_sensors);
    c_.breakaway_f_var =
        S::from_double(p.breakaway_friction_uncertainty_n * p.breakaway_friction_uncertainty_n);
    c_.kinetic_gain = S::from_double(-std::expm1(-dt / p.kinetic_friction_time_s));
    c_.bias_gain = S::from_double(-std::expm1(-dt / p.bias_time_s));
    c_.static_weight = S::from_double(p.static_friction_weight);
    c_.filter_gain = S::from_double(-std::expm1(-dt / p.acceleration_filter_time_s));
    c_.leak = S::from_double(std::exp(-dt / p.breakaway_leak_time_s));
    c_.stick_velocity = S::from_double(p.stick_velocity_m_per_s);
    c_.stick_acceleration = S::from_double(p.stick_acceleration_m_per_s2);
    c_.breakaway_velocity = S::from_double(p.breakaway_velocity_m_per_s);
    c_.slip_confidence = S::from_double(p.slip_confidence_m_per_s);
    c_.event_velocity = S::from_double(p.event_velocity_m_per_s);
    c_.gate_squared = S::from_double(p.event_gate_sigma * p.event_gate_sigma);
    c_.initial_kinetic = S::from_double(p.initial_kinetic_friction_n);
    c_.initial_static = S::from_double(p.initial_static_friction_n);
  }

 public:
  // Parked: stuck at x_r = x0 with the first floor sample a_u0; friction estimates from the
  // params.
  void reset(T a_u0, T x0_m = T(0)) noexcept {
    a_u_prev_ = S::is_finite(a_u0) ? a_u0 : T(0);
    kinetic_ = c_.initial_kinetic;
    static_ = c_.initial_static;
    bias_ = T(0);
    breakaways_ = 0;
    kinetic_samples_ = 0;
    rejected_ = 0;
    park(x0_m);
  }

  // One sample: a_u, and a_x and x_r where measured (a non-finite value means "not measured"; a
  // non-finite a_u is replaced by the previous one and counted).
  const StateEstimate<T>& step(T a_u, T a_x_measured, T x_r_measured) noexcept {
    if (!S::is_finite(a_u)) {
      a_u = a_u_prev_;
      ++rejected_;
    }
    const bool have_ax = S::is_finite(a_x_measured);
    const bool have_travel = S::is_finite(x_r_measured);
    // The measured relative acceleration without the learnt bias.
    const T a_rel = have_ax ? a_x_measured - a_u - bias_ : T(0);
    if (stuck_) {
      step_stuck(a_u, have_ax, a_x_measured - a_u, a_rel);
    }
    if (!stuck_) {
      step_slipping(a_u, have_ax, a_x_measured - bias_, a_rel);
    }
    if (have_travel) {
      update(T(1), T(0), T(0), x_r_measured - x_, c_.r_travel);
    } else if (stuck_) {
      // (Never a zero variance: the travel sensor's is added, F_fs may be 0.)
      const T band = static_ * c_.inv_stiffness;
      update(T(1), T(0), T(0), -x_, band * band + c_.r_travel);
    }
    T a_filtered_input = a_rel;
    if (!have_ax) {
      // The model's relative acceleration stands in for the measurement.
      a_filtered_input =
          stuck_ ? T(0) : -(c_.stiffness * x_ + c_.damping * v_ + f_) * c_.inv_mass - a_u;
    }
    a_filtered_ += c_.filter_gain * (a_filtered_input - a_filtered_);
    if (stuck_) {
      v_ = T(0);
      f_ = -(c_.stiffness * x_ + c_.mass * a_u);
      const T holding = S::abs(f_);
      if (holding > holding_peak_) holding_peak_ = holding;
    } else {
      if (S::abs(v_) < c_.stick_velocity && S::abs(a_filtered_) < c_.stick_acceleration) {
        stick();
        f_ = -(c_.stiffness * x_ + c_.mass * a_u);
      } else if (have_ax && S::abs(v_) > c_.slip_confidence) {
        // (Without a_x the force comes from the model whose F_fk is being estimated: no sample.)
        // A force against the Coulomb direction is a filter still settling after an event, not a
        // sample of F_fk.
        const T sample = v_ > T(0) ? f_ : -f_;
        if (sample > T(0)) {
          kinetic_ += c_.kinetic_gain * (sample - kinetic_);
          ++kinetic_samples_;
        }
        if (static_ < kinetic_) static_ = kinetic_;
      }
    }
    a_u_prev_ = a_u;
    a_rel_prev_ = a_rel;
    guard();
    publish();
    return estimate_;
  }
  const StateEstimate<T>& step_acceleration_only(T a_u, T a_x_measured) noexcept {
    return step(a_u, a_x_measured, not_measured());
  }
  const StateEstimate<T>& step_travel_only(T a_u, T x_r_measured) noexcept {
    return step(a_u, not_measured(), x_r_measured);
  }
  static T not_measured() noexcept { return std::numeric_limits<T>::quiet_NaN(); }

  const StateEstimate<T>& estimate() const noexcept { return estimate_; }
  // The variances the filter believes for x_r and v_r.
  T x_variance() const noexcept { return p_.xx; }
  T v_variance() const noexcept { return p_.vv; }
  std::uint64_t rejected_inputs() const noexcept { return rejected_; }
  std::uint64_t state_resets() const noexcept { return resets_; }
  bool configured() const noexcept { return configured_; }

 private:
  struct Covariance {
    T xx, xv, xf, vv, vf, ff;
  };
  struct Coefficients {
    Covariance q{};
    T q_stuck_xx{}, x_friction{}, v_friction{};
    T r_accel{}, r_travel{}, h_x{}, h_v{}, h_f{};
    T mass{}, stiffness{}, damping{}, inv_stiffness{}, inv_mass{}, dt{}, half_dt{},
        breakaway_f_var{}, breakaway_balance_var{};
    T kinetic_gain{}, bias_gain{}, static_weight{}, filter_gain{}, leak{};
    T stick_velocity{}, stick_acceleration{}, breakaway_velocity{}, slip_confidence{};
    T event_velocity{}, gate_squared{};
    T initial_kinetic{}, initial_static{};
  };

  void park(T x0) noexcept {
    x_ = x0;
    v_ = T(0);
    const T band = static_ * c_.inv_stiffness;
    p_ = Covariance{band * band, T(0), T(0), T(0), T(0), T(0)};
    f_ = -(c_.stiffness * x_ + c_.mass * a_u_prev_);
    a_filtered_ = T(0);
    a_rel_prev_ = T(0);
    stick();
    publish();
  }

  void stick() noexcept {
    stuck_ = true;
    v_ = T(0);
    breakaway_integral_ = T(0);
    holding_peak_ = T(0);
    p_.xv = p_.xf = p_.vv = p_.vf = p_.ff = T(0);
  }

  // Stuck: x_r held, v_r = 0. With a_x the relative acceleration is sensor error: its mean is the
  // bias, its leaky integral the break-away test. Without a_x the load decides.
  void step_stuck(T a_u, bool have_ax, T w, T a_rel) noexcept {
    p_.xx += c_.q_stuck_xx;
    T direction = T(0);
    T start_velocity = T(0);
    if (have_ax) {
      // Trapezoidal: the velocity the accelerometers see since the stick, at the step's start
      // and end.
      start_velocity = c_.leak * breakaway_integral_;
      breakaway_integral_ = start_velocity + c_.half_dt * (a_rel_prev_ + a_rel);
      if (S::abs(breakaway_integral_) > c_.breakaway_velocity) {
        direction = signum(breakaway_integral_);
      } else {
        bias_ += c_.bias_gain * (w - bias_);
      }
    } else {
      const T limit = -(c_.mass * a_u + c_.stiffness * x_);
      if (S::abs(limit) > static_) direction = signum(limit);
    }
    if (direction == T(0)) return;
    // Break-away: the largest holding force of the stuck phase is where the load passed F_fs.
    // (Only when the accelerometers saw it: a break-away the model decided says nothing new.)
    stuck_ = false;
    if (have_ax) {
      static_ += c_.static_weight * (holding_peak_ - static_);
      if (static_ < kinetic_) static_ = kinetic_;
      ++breakaways_;
    }
    // Restart the slip: v_r from the accelerometers since the stick (or zero without them)
    // (at the step's start: the slipping step that follows covers this sample's motion).
    v_ = start_velocity;
    p_.vv = v_ * v_ + c_.breakaway_velocity * c_.breakaway_velocity;
    if (have_ax) {
      // The force balance of this sample: within a few N, where F_fk's estimate may still be far.
      f_ = -(c_.mass * (a_rel + a_u) + c_.stiffness * x_ + c_.damping * v_);
      p_.ff = c_.breakaway_balance_var;
    } else {
      f_ = kinetic_ * direction;
      p_.ff = c_.breakaway_f_var;
    }
    p_.xv = p_.xf = p_.vf = T(0);
  }

  void step_slipping(T a_u, bool have_ax, T a_x, T a_rel) noexcept {
    const T g0 = -a_u_prev_, g1 = -a_u;
    const T v_before = v_;
    const T x1 = map_.xx * x_ + map_.xv * v_ + c_.x_friction * f_ + map_.gx0 * g0 + map_.gx1 * g1;
    const T v1 = map_.vx * x_ + map_.vv * v_ + c_.v_friction * f_ + map_.gv0 * g0 + map_.gv1 * g1;
    x_ = x1;
    v_ = v1;
    propagate(map_.xx, map_.xv, c_.x_friction, map_.vx, map_.vv, c_.v_friction, c_.q);
    // A reversal inside the step: the Coulomb force changes sign with v_r.
    if ((v_before > T(0) && v_ < T(0) && f_ > T(0)) ||
        (v_before < T(0) && v_ > T(0) && f_ < T(0))) {
      f_ = -f_;
      p_.xf = -p_.xf;
      p_.vf = -p_.vf;
    }
    if (!have_ax) return;
    T innovation = a_x - (c_.h_x * x_ + c_.h_v * v_ + c_.h_f * f_);
    if (S::abs(v_) < c_.event_velocity) {
      // Near v_r = 0 an innovation far outside the filter's belief is an event the prediction
      // missed (its v_r is a little off, the plant's crossed zero): a stick if the seat's relative
      // acceleration vanished, else a reversal if the flipped force explains the measurement
      // better. Left to the random walk, the jump would be smeared into v_r and F_f for tens of ms.
      const T ph0 = p_.xx * c_.h_x + p_.xv * c_.h_v + p_.xf * c_.h_f;
      const T ph1 = p_.xv * c_.h_x + p_.vv * c_.h_v + p_.vf * c_.h_f;
      const T ph2 = p_.xf * c_.h_x + p_.vf * c_.h_v + p_.ff * c_.h_f;
      const T variance = c_.h_x * ph0 + c_.h_v * ph1 + c_.h_f * ph2 + c_.r_accel;
      if (innovation * innovation > c_.gate_squared * variance) {
        if (S::abs(a_rel) < c_.stick_acceleration) {
          stick();
          return;
        }
        const T flipped = innovation + T(2) * c_.h_f * f_;
        if (S::abs(flipped) < S::abs(innovation)) {
          f_ = -f_;
          p_.xf = -p_.xf;
          p_.vf = -p_.vf;
          innovation = flipped;
        }
      }
    }
    update(c_.h_x, c_.h_v, c_.h_f, innovation, c_.r_accel);
  }

  // P <- A P A' + Q for A = [[a00, a01, a02], [a10, a11, a12], [0, 0, 1]].
  void propagate(T a00, T a01, T a02, T a10, T a11, T a12, const Covariance& q) noexcept {
    const Covariance& p = p_;
    const T r00 = a00 * p.xx + a01 * p.xv + a02 * p.xf;
    const T r01 = a00 * p.xv + a01 * p.vv + a02 * p.vf;
    const T r02 = a00 * p.xf + a01 * p.vf + a02 * p.ff;
    const T r10 = a10 * p.xx + a11 * p.xv + a12 * p.xf;
    const T r11 = a10 * p.xv + a11 * p.vv + a12 * p.vf;
    const T r12 = a10 * p.xf + a11 * p.vf + a12 * p.ff;
    Covariance n;
    n.xx = r00 * a00 + r01 * a01 + r02 * a02 + q.xx;
    n.xv = r00 * a10 + r01 * a11 + r02 * a12 + q.xv;
    n.vv = r10 * a10 + r11 * a11 + r12 * a12 + q.vv;
    n.xf = r02 + q.xf;
    n.vf = r12 + q.vf;
    n.ff = p.ff + q.ff;
    p_ = n;
  }

  // Scalar measurement h . [x_r, v_r, F_f] with the given innovation and variance r. One
  // division: the time-varying gain. While stuck only x_r is a state (the rest of P is zero).
  void update(T h0, T h1, T h2, T innovation, T r) noexcept {
    const T ph0 = p_.xx * h0 + p_.xv * h1 + p_.xf * h2;
    const T ph1 = p_.xv * h0 + p_.vv * h1 + p_.vf * h2;
    const T ph2 = p_.xf * h0 + p_.vf * h1 + p_.ff * h2;
    const T inv_s = T(1) / (h0 * ph0 + h1 * ph1 + h2 * ph2 + r);
    const T k0 = ph0 * inv_s, k1 = ph1 * inv_s, k2 = ph2 * inv_s;
    x_ += k0 * innovation;
    v_ += k1 * innovation;
    f_ += k2 * innovation;
    p_.xx -= k0 * ph0;
    p_.xv -= k0 * ph1;
    p_.xf -= k0 * ph2;
    p_.vv -= k1 * ph1;
    p_.vf -= k1 * ph2;
    p_.ff -= k2 * ph2;
  }

  // A non-finite state (only from a filter driven far outside its tuning) parks the seat where
  // the estimate last was finite instead of emitting NaN; the friction estimates survive.
  void guard() noexcept {
    if (S::is_finite(x_) && S::is_finite(v_) && S::is_finite(f_) && S::is_finite(p_.xx) &&
        S::is_finite(p_.vv) && S::is_finite(p_.ff) && S::is_finite(kinetic_) &&
        S::is_finite(static_) && S::is_finite(bias_)) {
      return;
    }
    if (!S::is_finite(kinetic_)) kinetic_ = c_.initial_kinetic;
    if (!S::is_finite(static_) || static_ < kinetic_) static_ = kinetic_;
    if (!S::is_finite(bias_)) bias_ = T(0);
    ++resets_;
    park(S::is_finite(estimate_.x_r_m) ? estimate_.x_r_m : T(0));
  }

  void publish() noexcept {
    estimate_.x_r_m = x_;
    estimate_.v_r_m_per_s = v_;
    estimate_.friction_n = f_;
    estimate_.kinetic_friction_n = kinetic_;
    estimate_.static_friction_n = static_;
    estimate_.bias_m_per_s2 = bias_;
    estimate_.relative_acceleration_m_per_s2 = a_filtered_;
    estimate_.stuck = stuck_;
    estimate_.breakaways = breakaways_;
    estimate_.kinetic_samples = kinetic_samples_;
  }

  Coefficients c_{};
  StepMap<T> map_{};
  Covariance p_{};
  StateEstimate<T> estimate_{};
  T x_{}, v_{}, f_{};
  T a_u_prev_{}, a_rel_prev_{}, a_filtered_{}, breakaway_integral_{}, holding_peak_{};
  T kinetic_{}, static_{}, bias_{};
  bool stuck_ = true;
  bool configured_ = false;
  std::uint32_t breakaways_ = 0;
  std::uint64_t kinetic_samples_ = 0;
  std::uint64_t rejected_ = 0, resets_ = 0;
};

}  // namespace stickslip
