#include "stickslip/host/run/advise.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/mat_file.hpp"
#include "stickslip/host/run/simulation.hpp"
#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip::host {
namespace {

constexpr double kCostTie = 1.10;

// Each part (one unless --gaps split cut the recording) run alone from rest; the figures over all
// parts from each part's sums: rms^2 times samples for T_ax, p and the cost times steps.
AdviseCandidate run_candidate(const AdviseRequest& request, const std::vector<SampledSignal>& parts,
                              double dt_s, FrictionModel model, Integrator integrator) {
  AdviseCandidate c;
  c.model = model;
  c.integrator = integrator;
  SimulationSetup setup;
  setup.params = request.params;
  setup.params.model = model;
  setup.params.integrator = integrator;
  setup.params.dt_s = dt_s;
  setup.repetitions = request.repetitions;
  SimulationTrace<double> trace;
  try {
    if (parts.size() == 1) {
      const SimulationSummary s = simulate_signal(setup, parts.front().a_u_m_per_s2, trace);
      c.configured = true;
      c.transmissibility = s.transmissibility;
      c.stick_probability = s.stick_probability;
      c.ns_per_sample = s.ns_per_sample;
      return c;
    }
    double sum_u = 0.0, sum_x = 0.0, samples = 0.0, stuck = 0.0, cost = 0.0, steps = 0.0;
    for (const SampledSignal& part : parts) {
      const SimulationSummary s = simulate_signal(setup, part.a_u_m_per_s2, trace);
      c.part_transmissibility.push_back(s.transmissibility);
      c.part_stick_probability.push_back(s.stick_probability);
      sum_u += s.rms_u * s.rms_u * static_cast<double>(s.samples);
      sum_x += s.rms_x * s.rms_x * static_cast<double>(s.samples);
      samples += static_cast<double>(s.samples);
      stuck += s.stick_probability * static_cast<double>(s.steps);
      cost += s.ns_per_sample * static_cast<double>(s.steps);
      steps += static_cast<double>(s.steps);
    }
    c.configured = true;
    c.transmissibility = std::sqrt(sum_x / samples) / std::sqrt(sum_u / samples);
    c.stick_probability = steps > 0.0 ? stuck / steps : 0.0;
    c.ns_per_sample = steps > 0.0 ? cost / steps : 0.0;
  } catch (const ConfigurationError& error) {
    c.refusal = error.what();
  }
  return c;
}

std::string label(const AdviseCandidate& c) {
  return fmt::format("{}/{}", model_name(c.model), integrator_name(c.integrator));
}

}  // namespace

AdviseReport advise(const AdviseRequest& request) {
  if (!std::isfinite(request.tolerance) || !(request.tolerance > 0.0))
    throw UsageError(fmt::format("--tolerance: must be > 0, got {}", request.tolerance));
  if (!(request.params.kinetic_friction_n >= 0.0))
    throw UsageError(fmt::format("--ffk: must be >= 0, got {}", request.params.kinetic_friction_n));
  const LoadedRecording recording = read_recording(request.input_path, request.recording);
  const std::vector<SampledSignal>& parts = recording.segments;
  const double dt_s = parts.front().dt_s;
  AdviseReport report;
  report.recording_note = describe_recording(request.input_path, recording.report);
  report.input_path = request.input_path;
  report.dt_s = dt_s;
  report.tolerance = request.tolerance;
  for (const SampledSignal& part : parts) {
    report.part_t_start_s.push_back(part.t_s.front());
    report.part_samples.push_back(part.a_u_m_per_s2.size());
  }

  report.reference =
      run_candidate(request, parts, dt_s, FrictionModel::stick_slip, Integrator::exact);
  if (!report.reference.configured) {
    throw HostError("the stick-slip reference cannot run these parameters: " +
                    report.reference.refusal);
  }
  const double reference = report.reference.transmissibility;
  report.reference.within_tolerance = true;
  // a0u and K as the simulation measures them.
  double sum = 0.0;
  std::size_t samples = 0;
  for (const SampledSignal& part : parts) {
    for (double value : part.a_u_m_per_s2) sum += value * value;
    samples += part.a_u_m_per_s2.size();
  }
  report.a0u = std::sqrt(sum / static_cast<double>(samples));
  report.k =
      den_hartog_factor(request.params.kinetic_friction_n, request.params.mass_kg, report.a0u);

  const std::pair<FrictionModel, Integrator> candidates[] = {
      {FrictionModel::linear, Integrator::exact},
      {FrictionModel::signum, Integrator::euler},
      {FrictionModel::signum, Integrator::symplectic},
      {FrictionModel::signum, Integrator::exact},
      {FrictionModel::smooth, Integrator::rk4},
      {FrictionModel::stick_slip, Integrator::euler},
      {FrictionModel::stick_slip, Integrator::symplectic},
      {FrictionModel::stick_slip, Integrator::rk4},
      {FrictionModel::stick_slip, Integrator::exact}};
  for (const auto& [model, integrator] : candidates) {
    AdviseCandidate c = (model == FrictionModel::stick_slip && integrator == Integrator::exact)
                            ? report.reference
                            : run_candidate(request, parts, dt_s, model, integrator);
    if (c.configured) {
      c.relative_error = reference > 0.0 ? std::fabs(c.transmissibility / reference - 1.0) : 0.0;
      c.within_tolerance = c.relative_error <= request.tolerance;
    }
    if (model == FrictionModel::signum && integrator == Integrator::euler) report.cheap = c;
    report.candidates.push_back(c);
  }
  report.reference.relative_error = 0.0;
  std::stable_sort(report.candidates.begin(), report.candidates.end(),
                   [](const AdviseCandidate& a, const AdviseCandidate& b) {
                     if (a.configured != b.configured) return a.configured;
                     return a.ns_per_sample < b.ns_per_sample;
                   });
  // The cheapest within tolerance; a more accurate one within 10 % of its cost wins the tie.
  for (std::size_t i = 0; i < report.candidates.size(); ++i) {
    const AdviseCandidate& c = report.candidates[i];
    if (!c.configured || !c.within_tolerance) continue;
    int best = static_cast<int>(i);
    for (std::size_t j = i + 1; j < report.candidates.size(); ++j) {
      const AdviseCandidate& d = report.candidates[j];
      if (d.configured && d.within_tolerance && d.ns_per_sample <= kCostTie * c.ns_per_sample &&
          d.relative_error < report.candidates[static_cast<std::size_t>(best)].relative_error) {
        best = static_cast<int>(j);
      }
    }
    report.chosen = best;
    break;
  }
  return report;
}

std::string format_advice(const AdviseReport& r) {
  std::string text =
      fmt::format("{}: dt = {} s, a0u = {:.4f} m/s^2, K = {:.3f} ({})\n", r.input_path, r.dt_s,
                  r.a0u, r.k, regime_name(friction_regime(r.k)));
  const double difference = r.cheap.transmissibility - r.reference.transmissibility;
  text += fmt::format(
      "cheap model signum/euler (Simulink ode1): T_ax = {:.4f}, p = {:.3f}\n"
      "stick-slip/exact (reference):             T_ax = {:.4f}, p = {:.3f}\n"
      "difference: T_ax {:+.4f} ({:+.2f} %), p {:+.3f}\n\n",
      r.cheap.transmissibility, r.cheap.stick_probability, r.reference.transmissibility,
      r.reference.stick_probability, difference,
      r.reference.transmissibility > 0.0 ? 100.0 * difference / r.reference.transmissibility : 0.0,
      r.cheap.stick_probability - r.reference.stick_probability);
  for (std::size_t i = 0; i < r.reference.part_transmissibility.size(); ++i) {
    const bool cheap = i < r.cheap.part_transmissibility.size();
    text += fmt::format(
        "part {} from t = {} s, {} samples, run alone: reference T_ax = {:.4f}, p = {:.3f}; "
        "signum/euler T_ax = {:.4f}, p = {:.3f}\n",
        i + 1, r.part_t_start_s[i], r.part_samples[i], r.reference.part_transmissibility[i],
        r.reference.part_stick_probability[i], cheap ? r.cheap.part_transmissibility[i] : 0.0,
        cheap ? r.cheap.part_stick_probability[i] : 0.0);
  }
  if (!r.reference.part_transmissibility.empty()) text += "\n";
  text += fmt::format("{:<24}{:>10}{:>8}{:>13}{:>12}  {}\n", "model/integrator", "T_ax", "p",
                      "T_ax error", "ns/sample", "within");
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const AdviseCandidate& c = r.candidates[i];
    if (!c.configured) {
      text += fmt::format("{:<24}  refused at this dt: {}\n", label(c), c.refusal);
      continue;
    }
    text += fmt::format("{:<24}{:>10.4f}{:>8.3f}{:>12.3f}%{:>12.1f}  {}{}\n", label(c),
                        c.transmissibility, c.stick_probability, 100.0 * c.relative_error,
                        c.ns_per_sample, c.within_tolerance ? "yes" : "no",
                        static_cast<int>(i) == r.chosen ? "  <- chosen" : "");
  }
  if (r.chosen >= 0) {
    const AdviseCandidate& c = r.candidates[static_cast<std::size_t>(r.chosen)];
    text += fmt::format(
        "\nadvice: {} - the cheapest model/integrator whose T_ax error ({:.3f} %) is within {:.3g} "
        "% at dt = {} s ({:.1f} ns/sample measured here).\n",
        label(c), 100.0 * c.relative_error, 100.0 * r.tolerance, r.dt_s, c.ns_per_sample);
  }
  return text;
}

}  // namespace stickslip::host
