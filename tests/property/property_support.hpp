// Random scenes for the property tests: parameters drawn over the physical ranges configure()
// accepts, with fixed seeds (SplitMix64: the same cases on every platform).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/oracles.hpp"
#include "stickslip/core/params.hpp"

namespace stickslip::test {

inline constexpr FrictionModel kAllModels[] = {FrictionModel::linear, FrictionModel::signum,
                                               FrictionModel::smooth, FrictionModel::stick_slip,
                                               FrictionModel::stribeck};
inline constexpr Integrator kAllIntegrators[] = {Integrator::euler, Integrator::symplectic,
                                                 Integrator::rk4, Integrator::exact};

inline double log_uniform(SplitMix64& random, double lo, double hi) {
  return std::exp(random.uniform(std::log(lo), std::log(hi)));
}

// m 20..200 kg, k 2..50 kN/m, damping ratio 0..2 (a quarter of the cases undamped), F_fk up to
// 300 N, F_fs 1..1.5 F_fk, v_S 1 mm/s..0.1 m/s, c 1..1e4 s/m, dt 0.1..5 ms.
inline OscillatorParams random_params(SplitMix64& random, FrictionModel model,
                                      Integrator integrator) {
  OscillatorParams p;
  p.model = model;
  p.integrator = integrator;
  p.mass_kg = random.uniform(20.0, 200.0);
  p.stiffness_n_per_m = log_uniform(random, 2e3, 5e4);
  const double zeta = random.uniform(0.0, 1.0) < 0.25 ? 0.0 : random.uniform(0.0, 2.0);
  p.damping_ns_per_m = zeta * 2.0 * std::sqrt(p.stiffness_n_per_m * p.mass_kg);
  p.kinetic_friction_n = random.uniform(0.0, 300.0);
  p.static_friction_n = p.kinetic_friction_n * random.uniform(1.0, 1.5);
  p.stribeck_velocity_m_per_s = log_uniform(random, 1e-3, 0.1);
  p.smoothing = static_cast<SmoothingLaw>(random.next() % 4);
  p.smoothing_constant_s_per_m = log_uniform(random, 1.0, 1e4);
  p.dt_s = log_uniform(random, 1e-4, 5e-3);
  return p;
}

// A bounded random input: a lorry-like signal with a random seed and RMS 0.1..3 m/s^2, with
// stretches held constant (where a stuck seat must stay stuck).
inline std::vector<double> random_input(SplitMix64& random, double dt_s, std::size_t steps) {
  const LorrySignal signal = make_lorry_signal(random.next(), random.uniform(0.1, 3.0));
  std::vector<double> out = signal.sample(dt_s, steps + 1);
  const std::size_t hold_from =
      static_cast<std::size_t>(random.uniform(0.3, 0.6) * static_cast<double>(steps));
  const std::size_t hold_to = hold_from + steps / 5;
  for (std::size_t n = hold_from + 1; n <= hold_to && n <= steps; ++n) out[n] = out[hold_from];
  return out;
}

inline double energy_j(const OscillatorParams& p, double x_m, double v_m_per_s) {
  return 0.5 * p.stiffness_n_per_m * x_m * x_m + 0.5 * p.mass_kg * v_m_per_s * v_m_per_s;
}

}  // namespace stickslip::test
