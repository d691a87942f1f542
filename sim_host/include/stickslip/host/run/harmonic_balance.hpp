// Steady-state amplitude of the seat under harmonic excitation a_u = A sin(w t), by harmonic
// balance (Den Hartog's approximate solution for combined Coulomb and viscous friction), against
// the simulated steady state.
//
// Derivation. In relative coordinates m x'' + b x' + k x + F_fk sgn(x') = -m a_u. Assume
// x = X sin(w t + phi). The first Fourier harmonic of F sgn(x') = F sgn(cos(w t + phi)) is
// (4 F / pi) cos(w t + phi) = c_eq x' with c_eq = 4 F / (pi w X) (an equivalent viscous damper).
// Balancing the sin and cos terms of the first harmonic, with psi the lag of x behind -m a_u:
//     (k - m w^2) X = m A cos(psi),   (b w X + 4 F / pi) = m A sin(psi), hence
//     ((k - m w^2) X)^2 + (b w X + 4 F / pi)^2 = (m A)^2,                              (11)
//     tan(psi) = (b w X + 4 F / pi) / ((k - m w^2) X).                                (12)
// (11) is a quadratic in X with D = (k - m w^2)^2 + (b w)^2, f = 4 F / pi:
//     X = [-b w f + sqrt((b w f)^2 + D ((m A)^2 - f^2))] / D,
// positive iff f < m A. With a0u = A / sqrt(2), Den Hartog's K = 4 F / (pi sqrt(2) m a0u)
// = f / (m A): the approximation has a (non-stop) solution only for K < 1. For b = 0 it is
// Den Hartog's X = (m A / |k - m w^2|) sqrt(1 - K^2) (J. P. Den Hartog, Forced vibrations with
// combined Coulomb and viscous friction, Trans. ASME APM-53-9, 1931; the equation numbers
// (11)-(12) are those the seed paper cites; the formulas are derived here, not copied). F -> 0
// gives the linear amplitude m A / sqrt(D) exactly. The assumption of continuous sinusoidal
// motion fails as K approaches 1: the mass sticks for part of each cycle.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"

namespace stickslip::host {

struct HarmonicBalance {
  bool valid = false;  // K < 1 (a non-stop solution exists)
  double k = 0.0;      // Den Hartog's K = 4 F_fk / (pi m A)
  double amplitude_m = 0.0;
  double phase_rad = 0.0;  // psi of (12), in [0, pi]
};

// Uses mass, stiffness, damping and kinetic friction of `params`; A > 0, frequency > 0.
// At b = 0 and w = w_n with K < 1 the amplitude is unbounded (returned as +inf, valid).
HarmonicBalance den_hartog_harmonic_balance(const OscillatorParams& params,
                                            double amplitude_m_per_s2, double frequency_hz);

struct SteadyState {
  double amplitude_m = 0.0;        // (max x_r - min x_r) / 2 over the measured periods
  double stick_probability = 0.0;  // over the measured periods
  double transmissibility = 0.0;   // over the measured periods
};

// Simulates params (model, integrator, dt from params) from the linear steady state for
// `periods` excitation periods and measures the last quarter of them.
SteadyState simulate_harmonic_steady_state(const OscillatorParams& params,
                                           double amplitude_m_per_s2, double frequency_hz,
                                           double periods);

struct HarmonicBalanceSweepRequest {
  double frequency_hz = 1.5;
  double amplitude_m_per_s2 = 0.49497474683058329;  // a0u = 0.35 m/s^2
  std::vector<double> damping_ns_per_m = {504.0, 0.0};
  std::string k_range = "0:1.5:31";
  double mass_kg = 88.4;
  double stiffness_n_per_m = 11500.0;
  double dt_s = 1e-3;
  double periods = 60.0;
};

// CSV: b_ns_per_m,K,ffk_n,hb_valid,x_hb_m,x_sim_m,x_linear_m,p_sim,T_ax_sim,rel_error
// (rel_error = x_hb / x_sim - 1; x_hb_m and rel_error are "nan" where hb_valid = 0, as there is
// no solution to compare, and a 0 would read as a perfect match). Returns the number of rows.
std::size_t write_harmonic_balance_sweep(const HarmonicBalanceSweepRequest& request,
                                         const std::string& path);

}  // namespace stickslip::host
