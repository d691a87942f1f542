#include "tradeoff/reference.hpp"

#include <chrono>
#include <cmath>

#include "stickslip/host/run/reference_solver.hpp"

namespace stickslip::tradeoff {
namespace {

double rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v * v;
  return values.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(values.size()));
}

}  // namespace

const char* reference_method() noexcept {
  return "stickslip::host::solve_reference "
         "(sim_host/include/stickslip/host/run/reference_solver.hpp: "
         "event-driven, closed form between events where the friction is constant, tight adaptive "
         "integration for the Stribeck and smoothed laws)";
}

Reference compute_reference(const OscillatorParams& params, const std::vector<double>& a_u) {
  Reference out;
  const auto start = std::chrono::steady_clock::now();
  host::ReferenceTrace trace = host::solve_reference(params, a_u);
  out.x_r_m = std::move(trace.x_r_m);
  out.a_x_m_per_s2 = std::move(trace.a_x_m_per_s2);
  out.stick_probability = trace.stuck_time_s / (static_cast<double>(a_u.size() - 1) * params.dt_s);
  out.events = trace.events;
  const double rms_u = rms(a_u);
  out.transmissibility = rms_u > 0.0 ? rms(out.a_x_m_per_s2) / rms_u : 0.0;
  out.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace stickslip::tradeoff
