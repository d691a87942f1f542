#include "fit_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stickslip::host {
namespace {

double& field(OscillatorParams& params, FitParameter parameter) {
  switch (parameter) {
    case FitParameter::mass:
      return params.mass_kg;
    case FitParameter::stiffness:
      return params.stiffness_n_per_m;
    case FitParameter::damping:
      return params.damping_ns_per_m;
    case FitParameter::ffk:
      return params.kinetic_friction_n;
    case FitParameter::ffs:
      return params.static_friction_n;
    case FitParameter::stribeck_velocity:
    default:
      return params.stribeck_velocity_m_per_s;
  }
}

std::size_t index_of(const FitProblem& problem, FitParameter parameter) {
  return static_cast<std::size_t>(std::find(problem.order.begin(), problem.order.end(), parameter) -
                                  problem.order.begin());
}

}  // namespace

std::vector<double> fit_values(const FitProblem& problem, const double* u) {
  const std::size_t count = problem.order.size();
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i) values[i] = problem.scale[i] * u[i];
  if (problem.static_excess) {
    values[index_of(problem, FitParameter::ffs)] += values[index_of(problem, FitParameter::ffk)];
  }
  return values;
}

std::vector<double> fit_value_jacobian(const FitProblem& problem) {
  const std::size_t count = problem.order.size();
  std::vector<double> jacobian(count * count, 0.0);
  for (std::size_t i = 0; i < count; ++i) jacobian[i * count + i] = problem.scale[i];
  if (problem.static_excess) {
    const std::size_t ffk = index_of(problem, FitParameter::ffk);
    jacobian[index_of(problem, FitParameter::ffs) * count + ffk] = problem.scale[ffk];
  }
  return jacobian;
}

OscillatorParams fit_params(const FitProblem& problem, const double* u) {
  OscillatorParams params = problem.base;
  const std::vector<double> values = fit_values(problem, u);
  for (std::size_t i = 0; i < values.size(); ++i) field(params, problem.order[i]) = values[i];
  // signum reads F_fk only; configure() still checks F_fs >= F_fk
  if (params.model == FrictionModel::signum || params.model == FrictionModel::linear)
    params.static_friction_n = params.kinetic_friction_n;
  return params;
}

namespace {

// Each part of a recording cut at its gaps starts from rest at its own first sample (v_r = 0,
// x_r measured or 0), as the whole recording does and as simulate --gaps split runs its parts: the
// state after a gap is unknown, and carrying the model's state over the gap would bridge it.
// T_ax and p over all parts, from each part's sums (rms^2 times samples, p times samples).
bool simulate_parts(const RigRecording& rig, SimulationSetup& setup, FitBuffers& buffers,
                    SimulationSummary& statistics) {
  SimulationTrace<double>& run = buffers.run;
  SimulationTrace<double>& part = buffers.part;
  run.resize(0);  // keeps the columns' capacity for the next evaluation
  double sum_u = 0.0, sum_x = 0.0, stuck = 0.0, samples = 0.0;
  for (std::size_t i = 0; i < rig.segment_count(); ++i) {
    const auto begin = static_cast<std::ptrdiff_t>(rig.segment_begin(i));
    const auto end = static_cast<std::ptrdiff_t>(rig.segment_end(i));
    buffers.part_a_u.assign(rig.a_u_m_per_s2.begin() + begin, rig.a_u_m_per_s2.begin() + end);
    setup.x0_m = rig.has_travel() ? rig.x_r_m[static_cast<std::size_t>(begin)] : 0.0;
    SimulationSummary summary;
    try {
      summary = simulate_signal(setup, buffers.part_a_u, part);
    } catch (const HostError&) {
      return false;  // parameters configure() refuses: the solver steps back
    }
    run.append(part);
    const auto n = static_cast<double>(summary.samples);
    sum_u += summary.rms_u * summary.rms_u * n;
    sum_x += summary.rms_x * summary.rms_x * n;
    stuck += summary.stick_probability * n;
    samples += n;
  }
  statistics.samples = static_cast<std::uint64_t>(samples);
  statistics.rms_u = std::sqrt(sum_u / samples);
  statistics.rms_x = std::sqrt(sum_x / samples);
  statistics.transmissibility = statistics.rms_x / statistics.rms_u;
  statistics.stick_probability = stuck / samples;
  return true;
}

}  // namespace

std::size_t fit_residual_count(const FitProblem& problem) {
  const std::size_t samples = problem.rig->a_x_m_per_s2.size();
  return problem.rig->has_travel() ? 2 * samples : samples;
}

bool fit_residuals(const FitProblem& problem, const double* u, std::vector<double>& residuals,
                   FitBuffers& buffers, SimulationSummary* summary) {
  const RigRecording& rig = *problem.rig;
  SimulationSetup setup;
  setup.params = fit_params(problem, u);
  setup.repetitions = 1;
  SimulationTrace<double>& run = buffers.run;
  SimulationSummary statistics;
  if (rig.segment_count() == 1) {
    setup.x0_m = rig.has_travel() ? rig.x_r_m[0] : 0.0;
    try {
      statistics = simulate_signal(setup, rig.a_u_m_per_s2, run);
    } catch (const HostError&) {
      return false;  // parameters configure() refuses: the solver steps back
    }
  } else if (!simulate_parts(rig, setup, buffers, statistics)) {
    return false;
  }
  const std::size_t samples = rig.a_x_m_per_s2.size();
  residuals.resize(fit_residual_count(problem));
  for (std::size_t n = 0; n < samples; ++n)
    residuals[n] = rig.a_x_m_per_s2[n] - run.a_x_m_per_s2[n];
  if (rig.has_travel()) {
    for (std::size_t n = 0; n < samples; ++n)
      residuals[samples + n] = problem.travel_weight * (rig.x_r_m[n] - run.x_r_m[n]);
  }
  if (summary != nullptr) *summary = statistics;
  return true;
}

double fit_cost(const FitProblem& problem, const double* u, FitBuffers& buffers) {
  if (!fit_residuals(problem, u, buffers.residuals, buffers))
    return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (double value : buffers.residuals) sum += value * value;
  return sum;
}

std::string fit_refusal(const FitProblem& problem, const double* u) {
  SimulationSetup setup;
  setup.params = fit_params(problem, u);
  setup.repetitions = 1;
  // configure() decides before the first step: two samples of the recording are enough.
  const std::vector<double>& a_u = problem.rig->a_u_m_per_s2;
  const std::vector<double> start(a_u.begin(),
                                  a_u.begin() + std::min<std::ptrdiff_t>(2, a_u.size()));
  SimulationTrace<double> run;
  try {
    simulate_signal(setup, start, run);
  } catch (const HostError& error) {
    return error.what();
  }
  return {};
}

bool fit_jacobian(const FitProblem& problem, const double* u, const std::vector<double>& lower,
                  const std::vector<double>& upper, double step, const std::vector<double>& base,
                  std::vector<double>& jacobian, FitBuffers& buffers) {
  const std::size_t count = problem.order.size();
  const std::size_t rows = base.size();
  jacobian.assign(rows * count, 0.0);
  std::vector<double> point(u, u + count);
  std::vector<double>& plus = buffers.plus;
  std::vector<double>& minus = buffers.minus;
  for (std::size_t j = 0; j < count; ++j) {
    point[j] = u[j] + step;
    const bool has_plus =
        point[j] <= upper[j] && fit_residuals(problem, point.data(), plus, buffers);
    point[j] = u[j] - step;
    const bool has_minus =
        point[j] >= lower[j] && fit_residuals(problem, point.data(), minus, buffers);
    point[j] = u[j];
    if (!has_plus && !has_minus) return false;
    double* column = jacobian.data() + j * rows;
    for (std::size_t n = 0; n < rows; ++n) {
      // residual = measured - model, so its derivative is minus the model's
      const double forward = has_plus ? (plus[n] - base[n]) / step : 0.0;
      const double backward = has_minus ? (base[n] - minus[n]) / step : 0.0;
      if (!has_minus) {
        column[n] = forward;
      } else if (!has_plus) {
        column[n] = backward;
      } else if (std::fabs(forward - backward) <=
                 0.5 * std::max(std::fabs(forward), std::fabs(backward)) + 1e-12 / step) {
        column[n] = 0.5 * (forward + backward);
      } else {
        column[n] = std::fabs(forward) < std::fabs(backward) ? forward : backward;
      }
    }
  }
  return true;
}

}  // namespace stickslip::host
