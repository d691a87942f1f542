// Closed forms, independent reference solutions and deterministic inputs for the core tests.
// Nothing here calls the library's step: every value is derived from the physics.
//
// The IEEE754 plugin fails a test on any underflow, overflow, invalid operation or division by
// zero, so the formulas below avoid exp() of large negative arguments and 0/0 by construction.
#pragma once

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/models/step_common.hpp"

namespace stickslip::test {

inline constexpr double kPi = 3.14159265358979323846;

// The reference seat (README.md): m, k, and b for a damping ratio of 0.25.
inline constexpr double kMassKg = 88.4;
inline constexpr double kStiffnessNPerM = 11500.0;
inline constexpr double kDampingNsPerM = 504.0;

inline OscillatorParams reference_params(FrictionModel model, Integrator integrator, double dt_s,
                                         double damping_ns_per_m = kDampingNsPerM) {
  OscillatorParams p;
  p.mass_kg = kMassKg;
  p.stiffness_n_per_m = kStiffnessNPerM;
  p.damping_ns_per_m = damping_ns_per_m;
  p.dt_s = dt_s;
  p.model = model;
  p.integrator = integrator;
  return p;
}

inline double natural_frequency_rad_s(double mass_kg, double stiffness_n_per_m) {
  return std::sqrt(stiffness_n_per_m / mass_kg);
}

// Den Hartog's K inverted: the kinetic friction that gives factor K at input RMS a0u.
inline double kinetic_friction_for_den_hartog(double k_factor, double mass_kg,
                                              double rms_m_per_s2) {
  return k_factor * kPi * std::sqrt(2.0) * mass_kg * rms_m_per_s2 / 4.0;
}

// Prints a measured margin when STICKSLIP_TEST_MARGINS is set (kept quiet otherwise), so that the
// figures behind a pass can be read with `STICKSLIP_TEST_MARGINS=1 test_core -v`.
inline void note_margin(const char* what, double measured, double limit) {
  if (std::getenv("STICKSLIP_TEST_MARGINS") == nullptr) return;
  std::printf("\n    [margin] %s: %.3e (limit %.3e)", what, measured, limit);
}

// SplitMix64: the same sequence on every platform and standard library (std::*_distribution is
// implementation-defined, which would make "deterministic" inputs differ between toolchains).
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    const double unit = static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * unit;
  }

 private:
  std::uint64_t state_;
};

// A random seat with dry friction, for sweeps of the event search: m 40-140 kg, k 3e3-3e4 N/m,
// b 0 (two seats in five) or up to 1000 N s/m, dt 1/2, 1 or 2 ms, F_fk 5-65 N with F_fs = F_fk
// (half the seats: the slip after a break-away starts with a_r = 0) or up to 1.5 F_fk, v_S 2-32
// mm/s; the exact integrator.
inline OscillatorParams random_sticking_seat(SplitMix64& random, FrictionModel model) {
  OscillatorParams p;
  p.model = model;
  p.integrator = Integrator::exact;
  p.mass_kg = random.uniform(40.0, 140.0);
  p.stiffness_n_per_m = 3.0e3 * std::pow(10.0, random.uniform(0.0, 1.0));
  p.damping_ns_per_m = random.uniform(0.0, 1.0) < 0.4 ? 0.0 : random.uniform(0.0, 1000.0);
  const double rate = random.uniform(0.0, 3.0);
  p.dt_s = rate < 1.0 ? 5e-4 : (rate < 2.0 ? 1e-3 : 2e-3);
  p.kinetic_friction_n = random.uniform(5.0, 65.0);
  p.static_friction_n =
      p.kinetic_friction_n * (random.uniform(0.0, 1.0) < 0.5 ? 1.0 : random.uniform(1.0, 1.5));
  p.stribeck_velocity_m_per_s = random.uniform(0.002, 0.032);
  return p;
}

// Floors for hostile runs of the event search, chosen sample by sample from the seat's own state:
// `holding` is the a_u at which F_L would be 0 there, `friction` F_fs / m. White noise up to
// 30 m/s^2; F_L held on +-F_fs (alternating every 7 samples, offsets down to 1e-8 m/s^2); swings
// of F_L over 1.5 to 9.5 F_fs.
enum class HostileFloor { noise, threshold, swing };
inline double hostile_floor(HostileFloor kind, long n, double holding, double friction,
                            SplitMix64& random) {
  switch (kind) {
    case HostileFloor::noise:
      return random.uniform(-30.0, 30.0);
    case HostileFloor::threshold: {
      const double side = (n / 7) % 2 == 0 ? -1.0 : 1.0;
      return holding - side * friction +
             random.uniform(-1.0, 1.0) * std::pow(10.0, random.uniform(-8.0, 0.0));
    }
    case HostileFloor::swing:
      break;
  }
  return holding + random.uniform(1.5, 9.5) * friction * random.uniform(-1.0, 1.0);
}

// Lorry-like cab-floor acceleration: five components between 1 and 3 Hz with random phases (the
// cab's heave and pitch band) plus 6.3 Hz and 12.6 Hz (wheel and engine orders), scaled to a
// given RMS. The RMS is the continuous-time one, sqrt(sum A_i^2 / 2).
struct LorrySignal {
  static constexpr int kComponents = 7;
  double frequency_hz[kComponents];
  double amplitude_m_per_s2[kComponents];
  double phase_rad[kComponents];

  double at(double t_s) const {
    double sum = 0.0;
    for (int i = 0; i < kComponents; ++i)
      sum += amplitude_m_per_s2[i] * std::sin(2.0 * kPi * frequency_hz[i] * t_s + phase_rad[i]);
    return sum;
  }
  double rms() const {
    double sum = 0.0;
    for (int i = 0; i < kComponents; ++i)
      sum += 0.5 * amplitude_m_per_s2[i] * amplitude_m_per_s2[i];
    return std::sqrt(sum);
  }
  // Samples a_u[n] = a(n dt), n = 0..count-1.
  std::vector<double> sample(double dt_s, std::size_t count) const {
    std::vector<double> out(count);
    for (std::size_t n = 0; n < count; ++n) out[n] = at(static_cast<double>(n) * dt_s);
    return out;
  }
};

inline LorrySignal make_lorry_signal(std::uint64_t seed, double rms_m_per_s2) {
  SplitMix64 random(seed);
  LorrySignal s{};
  const double low_band_hz[5] = {1.0, 1.45, 1.9, 2.4, 2.95};
  const double low_band_weight[5] = {1.0, 0.9, 1.0, 0.7, 0.5};
  for (int i = 0; i < 5; ++i) {
    s.frequency_hz[i] = low_band_hz[i];
    s.amplitude_m_per_s2[i] = low_band_weight[i];
    s.phase_rad[i] = random.uniform(0.0, 2.0 * kPi);
  }
  s.frequency_hz[5] = 6.3;
  s.amplitude_m_per_s2[5] = 0.6;
  s.phase_rad[5] = random.uniform(0.0, 2.0 * kPi);
  s.frequency_hz[6] = 12.6;
  s.amplitude_m_per_s2[6] = 0.35;
  s.phase_rad[6] = random.uniform(0.0, 2.0 * kPi);
  const double scale = rms_m_per_s2 / s.rms();
  for (double& a : s.amplitude_m_per_s2) a *= scale;
  return s;
}

// Sample j of the first-order-hold (linear) interpolation of `coarse` onto a grid `ratio` times
// finer: both grids then see the identical piecewise-linear a_u(t).
inline double refine_linear(const std::vector<double>& coarse, std::size_t j, std::size_t ratio) {
  const std::size_t i = j / ratio, r = j % ratio;
  if (r == 0) return coarse[i];
  const double w = static_cast<double>(r) / static_cast<double>(ratio);
  return (1.0 - w) * coarse[i] + w * coarse[i + 1];
}

// ---------------------------------------------------------------------------------------------
// Frequency response of the linear seat to a sampled harmonic under first-order hold.
//
// H(s) = X_r/A_u = -m / (m s^2 + b s + k). The FOH interpolation of the samples e^{i w n dt} is
// sum_k sinc^2(w_k dt/2) e^{i w_k t}, w_k = w + 2 pi k/dt (Poisson summation of the triangle
// kernel), so at the sample instants the steady state is
//   x[n] = e^{i w n dt} sum_k H(i w_k) sinc^2(w_k dt/2),  v[n] = e^{i w n dt} sum_k i w_k H(...)...
// The terms fall off as 1/k^4 (x) and, paired +k/-k, 1/k^4 (v).
struct PhasorResponse {
  std::complex<double> x_m;        // complex amplitude of x_r at the samples per unit input
  std::complex<double> v_m_per_s;  // same for v_r
};

inline std::complex<double> seat_frf(double m, double b, double k, double w) {
  // -m / (k - m w^2 + i b w), divided by hand (no library complex division and its scaling).
  const double re = k - m * w * w, im = b * w;
  const double den = re * re + im * im;
  return {-m * re / den, m * im / den};
}

inline PhasorResponse foh_phasor_response(double m, double b, double k, double w, double dt,
                                          int terms = 2000) {
  const double alpha = 0.5 * w * dt;
  const double sin_sq = std::sin(alpha) * std::sin(alpha);  // sin^2(alpha + pi k) = sin^2(alpha)
  std::complex<double> x(0.0, 0.0), v(0.0, 0.0);
  auto add = [&](int index) {
    const double wk = w + 2.0 * kPi * index / dt;
    const double s = alpha + kPi * index;
    const double weight = sin_sq / (s * s);
    const std::complex<double> h = seat_frf(m, b, k, wk) * weight;
    x += h;
    v += std::complex<double>(0.0, wk) * h;
  };
  for (int j = terms; j >= 1; --j) {  // smallest terms first
    add(j);
    add(-j);
  }
  add(0);
  return {x, v};
}

// ---------------------------------------------------------------------------------------------
// Coulomb friction under a constant base acceleration a_u, released at rest from x0 (b may be 0,
// the system must be under-damped). Between two instants where v_r = 0 the friction is the
// constant F_fk d, so the motion is a damped half oscillation about the shifted equilibrium
//   x_e = -(m a_u + F_fk d)/k,   d = sgn(F_L) at the release, F_L = -(m a_u + k x),
// lasting pi/omega_d and ending at x_e - e (x_start - x_e), e = exp(-sigma pi/omega_d). At its end
// the mass sticks if |F_L| <= F_fs, otherwise it reverses (d flips). This chains the half cycles.
struct CoulombHalfCycles {
  struct HalfCycle {
    double start_s;
    double x_start_m;
    double direction;  // +1/-1: sign of v_r during the half cycle
    double x_equilibrium_m;
  };
  static constexpr int kMaxHalfCycles = 256;

  HalfCycle cycle[kMaxHalfCycles];
  int count = 0;          // half cycles of slip before sticking
  bool sticks = false;    // false: more than kMaxHalfCycles half cycles
  double stop_s = 0.0;    // instant at which it sticks for good
  double stop_x_m = 0.0;  // and where
  double sigma = 0.0, omega0 = 0.0, omega_d = 0.0, half_period_s = 0.0;

  // Index of the half cycle containing t (the last one after the stop).
  int half_cycle_at(double t_s) const {
    int j = 0;
    while (j + 1 < count && t_s >= cycle[j + 1].start_s) ++j;
    return j;
  }
  // State at time t (t >= 0): on the half cycle containing t, or stuck at stop_x after stop_s.
  void state_at(double t_s, double& x_m, double& v_m_per_s) const {
    const int j = half_cycle_at(t_s);
    if (count == 0 || (sticks && t_s >= stop_s)) {
      x_m = stop_x_m;
      v_m_per_s = 0.0;
      return;
    }
    const HalfCycle& c = cycle[j];
    const double tau = t_s - c.start_s;
    const double y0 = c.x_start_m - c.x_equilibrium_m;
    const double decay = std::exp(-sigma * tau);  // sigma*tau <= sigma*pi/omega_d: harmless
    x_m = c.x_equilibrium_m +
          y0 * decay * (std::cos(omega_d * tau) + sigma / omega_d * std::sin(omega_d * tau));
    v_m_per_s = -y0 * (omega0 * omega0 / omega_d) * decay * std::sin(omega_d * tau);
  }
};

inline CoulombHalfCycles coulomb_half_cycles(double m, double k, double b, double kinetic_n,
                                             double static_n, double a_u, double x0_m) {
  CoulombHalfCycles r;
  r.omega0 = std::sqrt(k / m);
  r.sigma = b / (2.0 * m);
  r.omega_d = std::sqrt(r.omega0 * r.omega0 - r.sigma * r.sigma);
  r.half_period_s = kPi / r.omega_d;
  const double e = std::exp(-r.sigma * r.half_period_s);
  double t = 0.0, x = x0_m;
  for (;;) {
    const double limit = -(m * a_u + k * x);
    if (std::fabs(limit) <= static_n) {
      r.sticks = true;
      r.stop_s = t;
      r.stop_x_m = x;
      return r;
    }
    if (r.count == CoulombHalfCycles::kMaxHalfCycles) return r;
    const double d = limit > 0.0 ? 1.0 : -1.0;
    const double x_e = -(m * a_u + kinetic_n * d) / k;
    r.cycle[r.count++] = {t, x, d, x_e};
    x = x_e - e * (x - x_e);
    t += r.half_period_s;
  }
}

// Bit-for-bit equality (distinguishes -0 from +0, unlike ==).
template <typename T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Two step outputs equal field by field, bit for bit.
template <typename T>
bool same_bits(const StepOutput<T>& a, const StepOutput<T>& b) {
  return same_bits(a.x_r_m, b.x_r_m) && same_bits(a.v_r_m_per_s, b.v_r_m_per_s) &&
         same_bits(a.a_x_m_per_s2, b.a_x_m_per_s2) && same_bits(a.friction_n, b.friction_n) &&
         same_bits(a.stuck_time_s, b.stuck_time_s) &&
         same_bits(a.stuck_fraction, b.stuck_fraction) && a.stuck == b.stuck &&
         a.events == b.events;
}

// Mechanical energy of the relative motion, J.
inline double mechanical_energy_j(double m, double k, double x_m, double v_m_per_s) {
  return 0.5 * m * v_m_per_s * v_m_per_s + 0.5 * k * x_m * x_m;
}

}  // namespace stickslip::test
