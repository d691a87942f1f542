#include "tradeoff/measure.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "stickslip/models/dispatch.hpp"

#ifdef STICKSLIP_HAVE_CALLGRIND_H
#include <valgrind/callgrind.h>
#endif

namespace stickslip::tradeoff {
namespace {

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t n = 0; n < a.size(); ++n) sum += (a[n] - b[n]) * (a[n] - b[n]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

double rms(const std::vector<double>& a) {
  double sum = 0.0;
  for (const double v : a) sum += v * v;
  return std::sqrt(sum / static_cast<double>(a.size()));
}

double max_abs(const std::vector<double>& a) {
  double out = 0.0;
  for (const double v : a) out = std::max(out, std::fabs(v));
  return out;
}

double relative(double error, double scale) {
  return scale > 0.0 ? error / scale : error;
}

template <typename T>
const std::vector<T>& input_of(const SampledInput& input);
template <>
const std::vector<double>& input_of<double>(const SampledInput& input) {
  return input.as_double;
}
template <>
const std::vector<float>& input_of<float>(const SampledInput& input) {
  return input.as_float;
}

template <typename T>
Outcome run_typed(const OscillatorParams& params, const SampledInput& input,
                  const Reference& physics, const Timing& timing) {
  const std::vector<T>& a_u = input_of<T>(input);
  return with_oscillator<T>(params, [&](auto& oscillator) {
    Outcome outcome;
    const ConfigResult configured = oscillator.configure(params);
    if (!configured.ok()) {
      outcome.note = configured.message.c_str();
      outcome.status = refused_status(outcome.note);
      return outcome;
    }
    const bool sticking =
        params.model == FrictionModel::stick_slip || params.model == FrictionModel::stribeck;
    outcome.trace = trace_stream(oscillator, a_u, sticking);
    if (!outcome.trace.finite || oscillator.state_resets() > 0) {
      outcome.status = "unstable";
      outcome.note =
          fmt::format("non-finite state ({} restarts from rest)", oscillator.state_resets());
      return outcome;
    }
    const std::string reason = blow_up_reason(outcome.trace, physics);
    if (!reason.empty()) {
      outcome.status = "unstable";
      outcome.note = reason;
      return outcome;
    }
    if (oscillator.event_budget_exhausted() > 0) {
      outcome.note =
          fmt::format("event budget exhausted in {} steps", oscillator.event_budget_exhausted());
    }
    outcome.timing = time_stream(oscillator, a_u, timing);
    return outcome;
  });
}

template <typename T>
bool count_typed(const OscillatorParams& params, const SampledInput& input, std::size_t steps,
                 const std::string& name) {
  const std::vector<T>& a_u = input_of<T>(input);
  const std::size_t count = std::min(a_u.size(), steps + 1);
  return with_oscillator<T>(params, [&](auto& oscillator) {
    if (!oscillator.configure(params).ok()) return false;
    RunningStatistics<T> statistics;
#ifdef STICKSLIP_HAVE_CALLGRIND_H
    const std::string dump = fmt::format("{}#{}", name, count - 1);
    CALLGRIND_ZERO_STATS;
    CALLGRIND_TOGGLE_COLLECT;
    keep(stream(oscillator, a_u.data(), count, statistics));
    CALLGRIND_TOGGLE_COLLECT;
    CALLGRIND_DUMP_STATS_AT(dump.c_str());
#else
    (void)name;
#endif
    return true;
  });
}

}  // namespace

Errors compare(const RunTrace& trace, const Reference& reference) {
  Errors e;
  e.transmissibility_rel = relative(std::fabs(trace.transmissibility - reference.transmissibility),
                                    reference.transmissibility);
  if (trace.has_stick_state) {
    e.stick_prob_abs = std::fabs(trace.stick_probability - reference.stick_probability);
  }
  e.a_x_rms = rms_difference(trace.a_x_m_per_s2, reference.a_x_m_per_s2);
  e.a_x_rms_rel = relative(e.a_x_rms, rms(reference.a_x_m_per_s2));
  e.x_r_rms = rms_difference(trace.x_r_m, reference.x_r_m);
  e.x_r_rms_rel = relative(e.x_r_rms, rms(reference.x_r_m));
  return e;
}

std::string blow_up_reason(const RunTrace& trace, const Reference& reference) {
  const double x_max = max_abs(trace.x_r_m), x_limit = 10.0 * max_abs(reference.x_r_m) + 1.0;
  if (x_max > x_limit) {
    return fmt::format("max |x_r| {:.3g} m > {:.3g} m (10x the reference + 1 m)", x_max, x_limit);
  }
  const double a_rms = rms(trace.a_x_m_per_s2),
               a_limit = 100.0 * rms(reference.a_x_m_per_s2) + 10.0;
  if (a_rms > a_limit) {
    return fmt::format("RMS a_x {:.3g} m/s^2 > {:.3g} (100x the reference + 10)", a_rms, a_limit);
  }
  return {};
}

std::string refused_status(const std::string& message) {
  const std::size_t colon = message.find(':');
  return "refused: " + (colon == std::string::npos ? message : message.substr(0, colon));
}

Outcome run_library(const OscillatorParams& params, host::ScalarType scalar,
                    const SampledInput& input, const Reference& physics, const Timing& timing) {
  return scalar == host::ScalarType::float32 ? run_typed<float>(params, input, physics, timing)
                                             : run_typed<double>(params, input, physics, timing);
}

bool running_on_valgrind() noexcept {
#ifdef STICKSLIP_HAVE_CALLGRIND_H
  return RUNNING_ON_VALGRIND != 0;
#else
  return false;
#endif
}

bool count_library(const OscillatorParams& params, host::ScalarType scalar,
                   const SampledInput& input, std::size_t steps, const std::string& name) {
  return scalar == host::ScalarType::float32 ? count_typed<float>(params, input, steps, name)
                                             : count_typed<double>(params, input, steps, name);
}

const char* build_compiler() noexcept {
  return STICKSLIP_CXX_COMPILER;
}
const char* build_flags() noexcept {
  return STICKSLIP_CXX_FLAGS;
}
const char* build_type() noexcept {
  return STICKSLIP_BUILD_TYPE;
}

}  // namespace stickslip::tradeoff
