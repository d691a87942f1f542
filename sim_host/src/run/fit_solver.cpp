#include "fit_solver.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace stickslip::host {
namespace {

// The whole recording as one residual block: every evaluation is one exact simulation, and the
// Jacobian is fit_jacobian()'s (Ceres's own numeric differentiation would take central
// differences across the mode changes).
class RecordingCost final : public ceres::CostFunction {
 public:
  RecordingCost(const FitProblem& problem, const FitBox& box) : problem_(problem), box_(box) {
    set_num_residuals(static_cast<int>(fit_residual_count(problem)));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(problem.order.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!fit_residuals(problem_, parameters[0], base_, buffers_)) return false;
    std::copy(base_.begin(), base_.end(), residuals);
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    if (!fit_jacobian(problem_, parameters[0], box_.lower, box_.upper, box_.step, base_, columns_,
                      buffers_)) {
      return false;
    }
    const std::size_t rows = base_.size(), count = problem_.order.size();
    double* out = jacobians[0];
    for (std::size_t n = 0; n < rows; ++n)
      for (std::size_t j = 0; j < count; ++j) out[n * count + j] = columns_[j * rows + n];
    return true;
  }

 private:
  const FitProblem& problem_;
  const FitBox& box_;
  mutable std::vector<double> base_, columns_;
  mutable FitBuffers buffers_;
};

}  // namespace

LocalFit solve_local(const FitProblem& problem, const FitBox& box, std::vector<double> u0,
                     int max_iterations) {
  LocalFit fit;
  fit.u = std::move(u0);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem solver_problem(problem_options);
  solver_problem.AddResidualBlock(new RecordingCost(problem, box), nullptr, fit.u.data());
  for (std::size_t i = 0; i < fit.u.size(); ++i) {
    solver_problem.SetParameterLowerBound(fit.u.data(), static_cast<int>(i), box.lower[i]);
    solver_problem.SetParameterUpperBound(fit.u.data(), static_cast<int>(i), box.upper[i]);
  }
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  // The unknowns are of order 1 and their 95 % intervals are wider than 1e-4 of them: stopping at
  // a relative change of 1e-6 in u or 1e-8 in the cost is well inside every interval.
  options.function_tolerance = 1e-8;
  options.parameter_tolerance = 1e-6;
  options.gradient_tolerance = 1e-12;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &solver_problem, &summary);
  fit.cost = 2.0 * summary.final_cost;  // Ceres minimises half the sum of squares
  fit.iterations = static_cast<int>(summary.iterations.size()) - 1;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.message = summary.message;
  return fit;
}

std::vector<std::vector<double>> principal_axes(const FitProblem& problem, const FitBox& box,
                                                const std::vector<double>& u, double cost,
                                                FitBuffers& buffers, int* evaluations) {
  std::vector<std::vector<double>> axes;
  const std::size_t count = u.size();
  std::vector<double> residuals, columns;
  if (!fit_residuals(problem, u.data(), residuals, buffers) ||
      !fit_jacobian(problem, u.data(), box.lower, box.upper, box.step, residuals, columns,
                    buffers)) {
    return axes;
  }
  if (evaluations != nullptr) *evaluations += 1 + 2 * static_cast<int>(count);
  // Eigenvectors of s^2 (J'J)^-1 and the square roots of its eigenvalues. An unknown without
  // influence (a zero column) is searched along its own axis with the differencing step.
  const auto rows = static_cast<Eigen::Index>(residuals.size());
  const auto n = static_cast<Eigen::Index>(count);
  const Eigen::Map<const Eigen::MatrixXd> jacobian(columns.data(), rows, n);
  const double variance = cost / static_cast<double>(residuals.size() - count);
  Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
  for (Eigen::Index j = 0; j < n; ++j)
    if (normal(j, j) == 0.0) normal(j, j) = variance / (box.step * box.step);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normal);
  for (Eigen::Index a = 0; a < n; ++a) {
    const double curvature = eigen.eigenvalues()(a);
    if (!(curvature > 0.0)) continue;
    const double sd = std::sqrt(variance / curvature);
    std::vector<double> axis(count);
    for (Eigen::Index j = 0; j < n; ++j)
      axis[static_cast<std::size_t>(j)] = sd * eigen.eigenvectors()(j, a);
    axes.push_back(axis);
  }
  return axes;
}

PatternSearch pattern_search(const FitProblem& problem, const FitBox& box,
                             const std::vector<double>& start, double start_cost, double first_step,
                             double last_step, int max_evaluations, bool diagonals) {
  PatternSearch out{start, start_cost, 0, 0};
  const std::size_t count = start.size();
  FitBuffers buffers;
  std::vector<std::vector<double>> axes =
      principal_axes(problem, box, start, start_cost, buffers, &out.evaluations);
  if (axes.empty()) return out;
  if (diagonals) {
    // every sum of two or more axes with signs, sum_i c_i a_i / sqrt(#c_i != 0) with c_i in
    // {-1, 0, +1}, one of each pair +-c (the search tries both ways): one standard error long
    const std::size_t principal = axes.size();
    std::size_t patterns = 1;
    for (std::size_t a = 0; a < principal; ++a) patterns *= 3;
    for (std::size_t code = 1; code < patterns; ++code) {
      std::vector<int> c(principal);
      std::size_t rest = code, nonzero = 0;
      for (std::size_t a = 0; a < principal; ++a, rest /= 3) {
        c[a] = static_cast<int>(rest % 3) - 1;
        nonzero += c[a] != 0 ? 1 : 0;
      }
      // keep the one of +-c whose first non-zero entry is +1
      const auto first = std::find_if(c.begin(), c.end(), [](int v) { return v != 0; });
      if (nonzero < 2 || *first < 0) continue;
      std::vector<double> axis(count, 0.0);
      for (std::size_t a = 0; a < principal; ++a)
        for (std::size_t j = 0; j < count; ++j)
          axis[j] += c[a] * axes[a][j] / std::sqrt(static_cast<double>(nonzero));
      axes.push_back(axis);
    }
  }
  const auto cost_at = [&](const std::vector<double>& u) {
    ++out.evaluations;
    return fit_cost(problem, u.data(), buffers);
  };
  const auto inside = [&](const std::vector<double>& u) {
    for (std::size_t j = 0; j < count; ++j)
      if (!(u[j] >= box.lower[j] && u[j] <= box.upper[j])) return false;
    return true;
  };
  const auto along = [&](const std::vector<double>& axis, double length) {
    std::vector<double> u = out.u;
    for (std::size_t j = 0; j < count; ++j) u[j] += length * axis[j];
    return u;
  };
  for (double step = first_step; step >= last_step && out.evaluations < max_evaluations;) {
    bool moved = false;
    for (const std::vector<double>& axis : axes) {
      for (double sign : {1.0, -1.0}) {
        double length = sign * step;
        std::vector<double> u = along(axis, length);
        if (!inside(u) || out.evaluations >= max_evaluations) continue;
        double cost = cost_at(u);
        // a success along an axis is tried again twice as far while it keeps lowering the cost
        while (cost < out.cost) {
          out.u = u;
          out.cost = cost;
          ++out.moves;
          moved = true;
          length *= 2.0;
          u = along(axis, length);
          if (!inside(u) || out.evaluations >= max_evaluations) break;
          cost = cost_at(u);
        }
      }
    }
    if (!moved) step *= 0.5;
  }
  return out;
}

FitCovariance fit_covariance(const FitProblem& problem, const std::vector<double>& u,
                             const FitBox& box) {
  const std::size_t count = u.size();
  FitCovariance out;
  out.ci95.assign(count, std::numeric_limits<double>::infinity());
  out.ci95_hac.assign(count, std::numeric_limits<double>::infinity());
  out.no_influence.assign(count, false);
  out.correlation.assign(count, std::vector<double>(count, std::nan("")));
  std::vector<double> residuals, columns;
  FitBuffers buffers;
  if (!fit_residuals(problem, u.data(), residuals, buffers) ||
      !fit_jacobian(problem, u.data(), box.lower, box.upper, box.covariance_step, residuals,
                    columns, buffers)) {
    return out;
  }
  const auto rows = static_cast<Eigen::Index>(residuals.size());
  const Eigen::Map<const Eigen::MatrixXd> jacobian(columns.data(), rows,
                                                   static_cast<Eigen::Index>(count));
  const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), rows);
  const double variance = r.squaredNorm() / static_cast<double>(residuals.size() - count);
  // Unknowns that change no residual are left out: their interval is unbounded.
  std::vector<Eigen::Index> kept;
  for (std::size_t j = 0; j < count; ++j) {
    out.no_influence[j] = jacobian.col(static_cast<Eigen::Index>(j)).squaredNorm() == 0.0;
    if (!out.no_influence[j]) kept.push_back(static_cast<Eigen::Index>(j));
  }
  const auto used = static_cast<Eigen::Index>(kept.size());
  if (used == 0) return out;
  Eigen::MatrixXd normal(used, used);
  for (Eigen::Index a = 0; a < used; ++a)
    for (Eigen::Index b = 0; b < used; ++b)
      normal(a, b) = jacobian.col(kept[static_cast<std::size_t>(a)])
                         .dot(jacobian.col(kept[static_cast<std::size_t>(b)]));
  const Eigen::VectorXd scale = normal.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * normal * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  const double smallest = eigen.eigenvalues().minCoeff();
  out.condition_number = smallest > 0.0 ? eigen.eigenvalues().maxCoeff() / smallest
                                        : std::numeric_limits<double>::infinity();
  if (!(smallest > 0.0)) return out;
  const Eigen::MatrixXd inverse_scaled = scaled.inverse();
  Eigen::MatrixXd covariance_u =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(count));
  for (Eigen::Index a = 0; a < used; ++a)
    for (Eigen::Index b = 0; b < used; ++b)
      covariance_u(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]) =
          variance * scale(a) * inverse_scaled(a, b) * scale(b);
  const std::vector<double> map = fit_value_jacobian(problem);
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
      value_map(map.data(), static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(count));
  const Eigen::MatrixXd covariance = value_map * covariance_u * value_map.transpose();

  // The sandwich: scores g_t = J_t r_t (kept columns), their long-run covariance by Newey-West
  // with Bartlett weights 1 - l/(L+1), L from Andrews (1991): an AR(1) fitted to each score
  // series, alpha = sum 4 rho^2 s^4 / ((1-rho)^6 (1+rho)^2) / sum s^4 / (1-rho)^4,
  // L = 1.1447 (alpha N)^(1/3). White residuals give L = 0 and S = sum r_t^2 J_t J_t', which is
  // s^2 J'J up to the noise of the estimate.
  {
    Eigen::MatrixXd scores(rows, used);
    for (Eigen::Index a = 0; a < used; ++a)
      scores.col(a) = jacobian.col(kept[static_cast<std::size_t>(a)]).cwiseProduct(r);
    double numerator = 0.0, denominator = 0.0;
    for (Eigen::Index a = 0; a < used; ++a) {
      const auto g = scores.col(a);
      const double g00 = g.head(rows - 1).squaredNorm();
      const double rho = g00 > 0.0 ? g.tail(rows - 1).dot(g.head(rows - 1)) / g00 : 0.0;
      const double s2 =
          (g.tail(rows - 1) - rho * g.head(rows - 1)).squaredNorm() / static_cast<double>(rows - 1);
      const double s4 = s2 * s2;
      numerator += 4.0 * rho * rho * s4 / (std::pow(1.0 - rho, 6) * (1.0 + rho) * (1.0 + rho));
      denominator += s4 / std::pow(1.0 - rho, 4);
    }
    const double alpha = denominator > 0.0 ? numerator / denominator : 0.0;
    const double lag = std::floor(1.1447 * std::cbrt(alpha * static_cast<double>(rows)));
    out.hac_lag = static_cast<int>(std::fmin(lag, static_cast<double>(rows - 1)));
    const double r00 = r.head(rows - 1).squaredNorm();
    out.residual_lag1_correlation = r00 > 0.0 ? r.tail(rows - 1).dot(r.head(rows - 1)) / r00 : 0.0;
    Eigen::MatrixXd long_run = scores.transpose() * scores;
    for (int l = 1; l <= out.hac_lag; ++l) {
      const Eigen::MatrixXd gamma =
          scores.bottomRows(rows - l).transpose() * scores.topRows(rows - l);
      long_run +=
          (1.0 - static_cast<double>(l) / (out.hac_lag + 1.0)) * (gamma + gamma.transpose());
    }
    // Degrees of freedom as the classic estimate: N / (N - P).
    long_run *= static_cast<double>(rows) / static_cast<double>(rows - used);
    const Eigen::MatrixXd bread = scale.asDiagonal() * inverse_scaled * scale.asDiagonal();
    const Eigen::MatrixXd sandwich_kept = bread * long_run * bread;
    Eigen::MatrixXd sandwich_u =
        Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(count));
    for (Eigen::Index a = 0; a < used; ++a)
      for (Eigen::Index b = 0; b < used; ++b)
        sandwich_u(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]) =
            sandwich_kept(a, b);
    const Eigen::MatrixXd sandwich = value_map * sandwich_u * value_map.transpose();
    for (std::size_t i = 0; i < count; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      if (!out.no_influence[i] && sandwich(ii, ii) >= 0.0)
        out.ci95_hac[i] = 1.959963984540054 * std::sqrt(sandwich(ii, ii));
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    if (out.no_influence[i]) continue;
    out.ci95[i] = 1.959963984540054 * std::sqrt(covariance(ii, ii));
    for (std::size_t j = 0; j < count; ++j) {
      const auto jj = static_cast<Eigen::Index>(j);
      if (out.no_influence[j]) continue;
      out.correlation[i][j] =
          covariance(ii, jj) / std::sqrt(covariance(ii, ii) * covariance(jj, jj));
    }
  }
  return out;
}

}  // namespace stickslip::host
