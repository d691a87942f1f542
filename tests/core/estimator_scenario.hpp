// Truth the state estimator did not make, shared by its tests and its validation program
// (reliability/src/estimator_validation_main.cpp): a lorry-like floor input (seeded Gaussian noise
// band-limited to 1-20 Hz), an independent fine-step simulation of a stick-slip seat whose friction
// drifts, and sensors with noise, bias and quantisation. Host code (std::vector).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "stickslip/observer/state_estimator.hpp"

namespace stickslip::test {

struct EstimatorScenario {
  std::uint64_t seed = 1;
  double floor_rms_m_per_s2 = 0.5;
  double duration_s = 100.0;
  double dt_s = 1e-3;
  double mass_kg = 88.4, stiffness_n_per_m = 11500.0, damping_ns_per_m = 504.0;
  double kinetic_friction_n = 60.0;  // at t = 0
  double static_friction_n = 70.0;   // at t = 0
  double friction_drift = 0.2;       // both levels rise by this share over drift_time_s
  double drift_time_s = 100.0;
  double seat_noise_m_per_s2 = 0.02, seat_bias_m_per_s2 = 0.01;
  double floor_noise_m_per_s2 = 0.02, floor_bias_m_per_s2 = -0.005;
  double travel_noise_m = 3e-5, travel_resolution_m = 1e-4;
  int substeps = 32;  // of the truth simulation per sample
};

struct ScenarioSample {
  double t_s;
  double a_u_true, a_u, a_x, x_r_measured;           // input and sensors
  double x_r, v_r, friction_n, kinetic_n, static_n;  // truth
  bool stuck;
};

// Standard normal deviates by Box-Muller from a 64-bit Mersenne twister (the same numbers on every
// standard library, unlike std::normal_distribution).
class Gaussian {
 public:
  explicit Gaussian(std::uint64_t seed) : engine_(seed) {}
  double operator()() {
    if (have_spare_) {
      have_spare_ = false;
      return spare_;
    }
    const double u1 = (double(engine_() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = double(engine_() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(6.283185307179586 * u2);
    have_spare_ = true;
    return r * std::cos(6.283185307179586 * u2);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool have_spare_ = false;
};

// Direct form I biquad (RBJ cookbook high- and low-pass).
struct Biquad {
  double b0, b1, b2, a1, a2, x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  static Biquad make(bool high_pass, double f_hz, double q, double fs_hz) {
    const double w = 6.283185307179586 * f_hz / fs_hz, c = std::cos(w);
    const double alpha = std::sin(w) / (2.0 * q), a0 = 1.0 + alpha;
    const double g = high_pass ? (1.0 + c) / 2.0 : (1.0 - c) / 2.0;
    const double b1 = high_pass ? -(1.0 + c) : 1.0 - c;
    return Biquad{g / a0, b1 / a0, g / a0, -2.0 * c / a0, (1.0 - alpha) / a0};
  }
  double operator()(double x) {
    const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1;
    x1 = x;
    y2 = y1;
    y1 = y;
    return y;
  }
};

// Gaussian noise through a 2nd-order Butterworth high-pass at 1 Hz and a 4th-order Butterworth
// low-pass at 20 Hz, scaled to the RMS exactly; 5 s of filter start-up are discarded.
inline std::vector<double> lorry_floor(std::uint64_t seed, double rms, std::size_t count,
                                       double dt_s) {
  Gaussian noise(seed);
  const double fs = 1.0 / dt_s;
  Biquad hp = Biquad::make(true, 1.0, 0.7071067811865476, fs);
  Biquad lp1 = Biquad::make(false, 20.0, 0.5411961001461970, fs);
  Biquad lp2 = Biquad::make(false, 20.0, 1.3065629648763766, fs);
  const std::size_t warmup = std::size_t(5.0 * fs);
  std::vector<double> a(count);
  double sum_sq = 0.0;
  for (std::size_t n = 0; n < warmup + count; ++n) {
    const double y = lp2(lp1(hp(noise())));
    if (n >= warmup) {
      a[n - warmup] = y;
      sum_sq += y * y;
    }
  }
  const double scale = rms / std::sqrt(sum_sq / double(count));
  for (double& v : a) v *= scale;
  return a;
}

// The seat by semi-implicit Euler on `substeps` sub-steps per sample with the floor input linear
// between samples; a slip ends where v_r reaches zero inside a sub-step, then the load decides
// between sticking (|F_L| <= F_fs) and reversing. Independent of the library's integrators and
// event search; its event timing error is one sub-step.
inline std::vector<ScenarioSample> make_scenario(const EstimatorScenario& sc) {
  const std::size_t count = std::size_t(std::llround(sc.duration_s / sc.dt_s)) + 1;
  const std::vector<double> a_u = lorry_floor(sc.seed, sc.floor_rms_m_per_s2, count, sc.dt_s);
  Gaussian seat_noise(sc.seed * 7919u + 1u), floor_noise(sc.seed * 7919u + 2u),
      travel_noise(sc.seed * 7919u + 3u);
  const double m = sc.mass_kg, k = sc.stiffness_n_per_m, b = sc.damping_ns_per_m;
  const double h = sc.dt_s / sc.substeps;
  double x = 0.0, v = 0.0, direction = 0.0;
  bool stuck = true;
  std::vector<ScenarioSample> out(count);
  for (std::size_t n = 0; n < count; ++n) {
    const double t = double(n) * sc.dt_s;
    const double drift = 1.0 + sc.friction_drift * std::fmin(t / sc.drift_time_s, 1.0);
    const double kinetic = sc.kinetic_friction_n * drift, fstatic = sc.static_friction_n * drift;
    if (n > 0) {
      for (int j = 0; j < sc.substeps; ++j) {
        const double a = a_u[n - 1] + (a_u[n] - a_u[n - 1]) * (double(j) + 0.5) / sc.substeps;
        if (stuck) {
          const double load = -(m * a + k * x);
          if (std::fabs(load) <= fstatic) continue;
          stuck = false;
          direction = load > 0.0 ? 1.0 : -1.0;
        }
        const double acc = (-k * x - b * v - kinetic * direction) / m - a;
        const double v_new = v + h * acc;
        if (v_new * direction <= 0.0) {
          x += 0.5 * h * v;
          v = 0.0;
          const double load = -(m * a + k * x);
          if (std::fabs(load) <= fstatic) {
            stuck = true;
          } else {
            direction = load > 0.0 ? 1.0 : -1.0;
          }
        } else {
          v = v_new;
          x += h * v;
        }
      }
    }
    ScenarioSample& s = out[n];
    s.t_s = t;
    s.a_u_true = a_u[n];
    s.x_r = x;
    s.v_r = v;
    s.stuck = stuck;
    s.friction_n = stuck ? -(k * x + m * a_u[n]) : kinetic * direction;
    s.kinetic_n = kinetic;
    s.static_n = fstatic;
    const double a_x = stuck ? a_u[n] : -(k * x + b * v + s.friction_n) / m;
    s.a_x = a_x + sc.seat_bias_m_per_s2 + sc.seat_noise_m_per_s2 * seat_noise();
    s.a_u = a_u[n] + sc.floor_bias_m_per_s2 + sc.floor_noise_m_per_s2 * floor_noise();
    const double travel = x + sc.travel_noise_m * travel_noise();
    s.x_r_measured = sc.travel_resolution_m * std::nearbyint(travel / sc.travel_resolution_m);
  }
  return out;
}

// The estimator's start: the reference seat's k, b, m (known), F_fk = F_fs = 45 N, the sensors'
// noise as specified.
inline StateEstimatorParams estimator_params(const EstimatorScenario& sc) {
  StateEstimatorParams p;
  p.mass_kg = sc.mass_kg;
  p.stiffness_n_per_m = sc.stiffness_n_per_m;
  p.damping_ns_per_m = sc.damping_ns_per_m;
  p.initial_kinetic_friction_n = 45.0;
  p.initial_static_friction_n = 45.0;
  p.dt_s = sc.dt_s;
  p.seat_acceleration_noise_m_per_s2 = sc.seat_noise_m_per_s2;
  p.floor_acceleration_noise_m_per_s2 = sc.floor_noise_m_per_s2;
  p.travel_noise_m = sc.travel_noise_m;
  p.travel_resolution_m = sc.travel_resolution_m;
  return p;
}

enum class Sensors { acceleration_and_travel, acceleration_only, travel_only };

struct EstimatorErrors {
  double v_r_rms_relative;        // RMS(v error) / RMS(v_r), whole run
  double x_r_rms_m;               // RMS(x error), whole run
  double friction_rms_relative;   // RMS(F_f error / F_fk(t)) over t > 10 s
  double kinetic_max_relative;    // max |F_fk error| / F_fk(t) over t >= 20 s
  double kinetic_final_relative;  // F_fk error / F_fk at the end (signed)
  double static_final_relative;   // F_fs error / F_fs at the end (signed)
  double kinetic_convergence_s;   // from then on |F_fk error| <= 5 % of F_fk(t)
  double friction_convergence_s;  // from then on every 1 s block's F_f RMS error <= 10 % F_fk
  double stuck_agreement;         // share of samples whose stuck state is the truth's
  double stick_share;             // the truth's share of stuck samples
};

struct TraceRow {
  double t_s, v_r, v_hat, x_r, x_hat, friction, friction_hat, kinetic, kinetic_hat, fstatic,
      static_hat;
  bool stuck, stuck_hat;
};

// Runs the estimator over the scenario with the given sensors; `trace` (if not null) gets every
// `trace_every`-th sample.
template <typename T>
EstimatorErrors run_estimator(const std::vector<ScenarioSample>& samples,
                              const StateEstimatorParams& params, Sensors sensors,
                              std::vector<TraceRow>* trace = nullptr,
                              std::size_t trace_every = 10) {
  static StateEstimator<T> estimator;
  EstimatorErrors e{};
  if (!estimator.configure(params).ok() || samples.empty()) return e;
  estimator.reset(T(samples[0].a_u));
  double v_err2 = 0, v_sq = 0, x_err2 = 0, f_err2 = 0, block_err2 = 0;
  std::size_t f_count = 0, block_count = 0, agree = 0, stuck_true = 0;
  double last_kinetic_out = 0.0, last_block_out = 0.0;
  const double block_s = 1.0;
  double block_start = 0.0;
  for (std::size_t n = 0; n < samples.size(); ++n) {
    const ScenarioSample& s = samples[n];
    const StateEstimate<T>* est = &estimator.estimate();
    if (n > 0) {
      const T a_x = sensors == Sensors::travel_only ? StateEstimator<T>::not_measured() : T(s.a_x);
      const T x = sensors == Sensors::acceleration_only ? StateEstimator<T>::not_measured()
                                                        : T(s.x_r_measured);
      est = &estimator.step(T(s.a_u), a_x, x);
    }
    const double v_hat = double(est->v_r_m_per_s), x_hat = double(est->x_r_m);
    const double f_hat = double(est->friction_n), ffk_hat = double(est->kinetic_friction_n);
    v_err2 += (v_hat - s.v_r) * (v_hat - s.v_r);
    v_sq += s.v_r * s.v_r;
    x_err2 += (x_hat - s.x_r) * (x_hat - s.x_r);
    const double f_rel = (f_hat - s.friction_n) / s.kinetic_n;
    if (s.t_s > 10.0) {
      f_err2 += f_rel * f_rel;
      ++f_count;
    }
    block_err2 += f_rel * f_rel;
    ++block_count;
    if (s.t_s - block_start >= block_s) {
      if (std::sqrt(block_err2 / double(block_count)) > 0.10) last_block_out = s.t_s;
      block_err2 = 0;
      block_count = 0;
      block_start = s.t_s;
    }
    const double k_rel = (ffk_hat - s.kinetic_n) / s.kinetic_n;
    if (std::fabs(k_rel) > 0.05) last_kinetic_out = s.t_s;
    if (s.t_s >= 20.0) e.kinetic_max_relative = std::fmax(e.kinetic_max_relative, std::fabs(k_rel));
    agree += est->stuck == s.stuck ? 1 : 0;
    stuck_true += s.stuck ? 1 : 0;
    if (n + 1 == samples.size()) {
      e.kinetic_final_relative = k_rel;
      e.static_final_relative = (double(est->static_friction_n) - s.static_n) / s.static_n;
    }
    if (trace && n % trace_every == 0) {
      trace->push_back(TraceRow{s.t_s, s.v_r, v_hat, s.x_r, x_hat, s.friction_n, f_hat, s.kinetic_n,
                                ffk_hat, s.static_n, double(est->static_friction_n), s.stuck,
                                est->stuck});
    }
  }
  const double count = double(samples.size());
  e.v_r_rms_relative = std::sqrt(v_err2 / v_sq);
  e.x_r_rms_m = std::sqrt(x_err2 / count);
  e.friction_rms_relative = f_count ? std::sqrt(f_err2 / double(f_count)) : 0.0;
  e.kinetic_convergence_s = last_kinetic_out;
  e.friction_convergence_s = last_block_out;
  e.stuck_agreement = double(agree) / count;
  e.stick_share = double(stuck_true) / count;
  return e;
}

}  // namespace stickslip::test
