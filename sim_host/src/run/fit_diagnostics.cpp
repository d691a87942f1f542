#include "fit_diagnostics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

long best_lag_samples(const std::vector<double>& measured, const std::vector<double>& model,
                      double dt_s) {
  const long count = static_cast<long>(std::min(measured.size(), model.size()));
  const long reach = std::min(static_cast<long>(std::lround(0.25 / dt_s)), count / 4);
  double best = -1.0;
  long best_lag = 0;
  for (long lag = -reach; lag <= reach; ++lag) {
    double sum = 0.0, measured_energy = 0.0, model_energy = 0.0;
    for (long n = std::max(0L, -lag); n < count && n + lag < count; ++n) {
      const double a = measured[static_cast<std::size_t>(n + lag)];
      const double b = model[static_cast<std::size_t>(n)];
      sum += a * b;
      measured_energy += a * a;
      model_energy += b * b;
    }
    const double correlation = sum / std::sqrt(measured_energy * model_energy + 1e-300);
    if (correlation > best) {
      best = correlation;
      best_lag = lag;
    }
  }
  return best_lag;
}

long StuckLags::best() const {
  long best_lag = 0;
  for (long lag = -reach; lag <= reach; ++lag) {
    const bool more = at(lag) > at(best_lag);
    const bool nearer = at(lag) == at(best_lag) && std::labs(lag) < std::labs(best_lag);
    if (more || nearer) best_lag = lag;
  }
  return best_lag;
}

StuckLags stuck_lags(const RigRecording& rig, const RigInspection& data) {
  const std::vector<double>& a_u = rig.a_u_m_per_s2;
  const std::vector<double>& a_x = rig.a_x_m_per_s2;
  const long count = static_cast<long>(std::min(a_u.size(), a_x.size()));
  StuckLags out;
  out.reach = std::min(static_cast<long>(std::lround(0.25 / rig.dt_s)), count / 4);
  out.counts.assign(static_cast<std::size_t>(2 * out.reach + 1), 0);
  const double threshold = stuck_threshold_m_per_s2(data);
  std::vector<std::uint8_t> stuck;
  for (long lag = -out.reach; lag <= out.reach; ++lag) {
    const long first = std::max(0L, -lag), end = std::min(count, count - lag);
    mark_stuck(a_x.data() + first + lag, a_u.data() + first, static_cast<std::size_t>(end - first),
               threshold, stuck);
    std::size_t in_phases = 0, run = 0;
    for (std::uint8_t flag : stuck) {
      if (flag != 0) {
        ++run;
        continue;
      }
      if (run >= kStuckPhaseSamples) in_phases += run;
      run = 0;
    }
    if (run >= kStuckPhaseSamples) in_phases += run;
    out.counts[static_cast<std::size_t>(lag + out.reach)] = in_phases;
  }
  return out;
}

namespace {

bool is_a_shift(long lag, double dt_s) {
  return std::labs(lag) >= 3 && std::fabs(static_cast<double>(lag) * dt_s) >= 3e-3;
}

[[noreturn]] void refuse_shift(const RigRecording& rig, long lag, const std::string& why) {
  throw HostError(fmt::format(
      "{}: a_x is shifted by {} samples ({:.4g} ms, {}) against a_u: {}", rig.path, std::labs(lag),
      1e3 * std::fabs(static_cast<double>(lag) * rig.dt_s), lag > 0 ? "late" : "early", why));
}

}  // namespace

bool check_stuck_alignment(const RigRecording& rig, const RigInspection& data) {
  // A shift shows as stuck samples that appear only with a_x moved against a_u. The stuck phases
  // decide when the lag with the most holds 1 % of the samples and 8 times the median over the
  // lags: where a seat hardly sticks, runs of a_x - a_u within the noise also occur by chance
  // (up to 0.55 % of the samples at some lag on the fit's validation rigs with K = 0.15, where
  // the seat sticks for 0.1 %). Then aligned when that lag is under the shift the check refuses,
  // shifted when the unshifted count is under half of it; in between (a floor so slow that
  // neighbouring lags look stuck as well) they cannot tell.
  const StuckLags stuck = stuck_lags(rig, data);
  if (stuck.reach == 0) return false;
  const long lag = stuck.best();
  const std::size_t most = stuck.at(lag), unshifted = stuck.at(0);
  std::vector<std::size_t> counts = stuck.counts;
  const auto middle = counts.begin() + static_cast<std::ptrdiff_t>(counts.size() / 2);
  std::nth_element(counts.begin(), middle, counts.end());
  const std::size_t samples = std::min(rig.a_u_m_per_s2.size(), rig.a_x_m_per_s2.size());
  if (100 * most < samples || most < 8 * *middle || most < kStuckPhaseSamples) return false;
  if (!is_a_shift(lag, rig.dt_s)) return true;
  if (2 * unshifted >= most) return false;
  refuse_shift(rig, lag,
               fmt::format("where the seat sticks a_x equals a_u, and the stuck phases hold {} "
                           "samples at that shift against {} unshifted; align the channels",
                           most, unshifted));
}

void check_model_alignment(const RigRecording& rig, const std::vector<double>& model_a_x) {
  const long lag = best_lag_samples(rig.a_x_m_per_s2, model_a_x, rig.dt_s);
  if (!is_a_shift(lag, rig.dt_s)) return;
  refuse_shift(rig, lag,
               "the measured a_x matches the model best at that lag; align the channels (a seat "
               "model cannot delay its response), or, if they are aligned, the model does not fit "
               "the seat (another --model, or other --start values of what is not fitted)");
}

namespace {

std::string name_of(const FitResult& result, std::size_t i) {
  return fit_parameter_name(result.order[i]);
}

double relative_ci(const FitResult& result, std::size_t i) {
  const auto k = static_cast<std::size_t>(result.order[i]);
  return result.ci95[k] / std::fabs(result.value[k]);
}

}  // namespace

std::vector<std::string> fit_warnings(const FitResult& result, const FitCovariance& covariance,
                                      const RigInspection& data, const FitBox& box,
                                      const std::vector<double>& u) {
  std::vector<std::string> warnings;
  const std::size_t count = result.order.size();
  const bool fits_static =
      std::find(result.order.begin(), result.order.end(), FitParameter::ffs) != result.order.end();
  if (fits_static && data.stuck_phases == 0) {
    warnings.push_back(fmt::format(
        "the data show no stick phase of {} samples or more (a_x following a_u): where the seat "
        "sticks only briefly, the break-away force F_fs is hardly seen, so ffk and ffs may not be "
        "told apart here",
        kStuckPhaseSamples));
  }
  // A fit of the right model leaves the sensors' noise (ratio about 1); twice that is structure
  // the model missed, and the intervals, which take the residual for white noise, are too narrow.
  if (result.noise_m_per_s2 > 0.0 && result.rms_residual_m_per_s2 > 2.0 * result.noise_m_per_s2) {
    warnings.push_back(fmt::format(
        "the rms residual {:.4g} m/s^2 is {:.3g} times the white noise in a_x ({:.4g} m/s^2): the "
        "model does not fit this recording to its noise (a local minimum of the fit, an effect "
        "the model lacks, or channels that do not line up), and the 95 % intervals, which take "
        "the residual for white noise, are too narrow",
        result.rms_residual_m_per_s2, result.rms_residual_m_per_s2 / result.noise_m_per_s2,
        result.noise_m_per_s2));
  }
  for (std::size_t i = 0; i < count; ++i) {
    // The solver stops a hair inside an active bound (Ceres keeps iterates strictly feasible),
    // so "on" it is within a millionth of it (u is scaled to order 1).
    const auto near = [&u, i](double bound) {
      return std::fabs(u[i] - bound) <= 1e-6 * std::max(1.0, std::fabs(bound));
    };
    const bool static_on_kinetic = result.order[i] == FitParameter::ffs && near(box.lower[i]) &&
                                   std::find(result.order.begin(), result.order.end(),
                                             FitParameter::ffk) != result.order.end();
    if (static_on_kinetic && !(relative_ci(result, i) <= 0.2)) {
      warnings.push_back(fmt::format(
          "ffk and ffs cannot be told apart on this recording: the fit puts ffs on ffk ({:.4g} N, "
          "the lowest it may be) with a 95 % interval of +-{:.3g} N; too few break-aways reach "
          "the static force",
          result.value[static_cast<std::size_t>(FitParameter::ffs)],
          result.ci95[static_cast<std::size_t>(FitParameter::ffs)]));
      continue;
    }
    if (covariance.no_influence[i]) {
      warnings.push_back(
          fmt::format("{} has no influence on the model on this recording: not identifiable",
                      name_of(result, i)));
    } else if (relative_ci(result, i) > 0.2) {
      warnings.push_back(fmt::format("{} is poorly determined: 95 % interval +-{:.3g} %",
                                     name_of(result, i), 100.0 * relative_ci(result, i)));
    }
    if (near(box.lower[i]) || near(box.upper[i]) || u[i] < box.lower[i] || u[i] > box.upper[i]) {
      warnings.push_back(
          fmt::format("{} ended on its bound: the estimate is the bound, not a "
                      "minimum",
                      name_of(result, i)));
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t j = i + 1; j < count; ++j) {
      const double rho = covariance.correlation[i][j];
      if (!(std::fabs(rho) > 0.9)) continue;
      warnings.push_back(fmt::format(
          "{} and {} are hard to tell apart on this recording: correlation {:+.3f} (a change in "
          "one is largely made up by the other; 95 % intervals +-{:.3g} % and +-{:.3g} %)",
          name_of(result, i), name_of(result, j), rho, 100.0 * relative_ci(result, i),
          100.0 * relative_ci(result, j)));
    }
  }
  return warnings;
}

}  // namespace stickslip::host
