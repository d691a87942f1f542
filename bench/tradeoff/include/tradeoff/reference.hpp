// The reference every run is compared with: one function, so that the harness does not care how
// the reference is computed.
#pragma once

#include <cstdint>
#include <vector>

#include "stickslip/core/params.hpp"

namespace stickslip::tradeoff {

struct Reference {
  std::vector<double> x_r_m, a_x_m_per_s2;  // one per input sample, [0] = initial state
  double transmissibility = 0.0;            // RMS(a_x)/RMS(a_u) over the same rows as a run's
  double stick_probability = 0.0;           // time stuck / total time
  std::uint64_t events = 0;
  double solve_seconds = 0.0;  // wall time of the solve (reported, not part of any result)
};

// The reference solution of `params` (model, law, friction; the integrator is ignored) for the
// input a_u sampled at params.dt_s with first-order hold between samples, from rest.
Reference compute_reference(const OscillatorParams& params, const std::vector<double>& a_u);

// One line for the report: how the reference is computed.
const char* reference_method() noexcept;

}  // namespace stickslip::tradeoff
