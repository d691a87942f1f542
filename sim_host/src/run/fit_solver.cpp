#include "fit_solver.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
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
    if (!fit_residuals(problem_, parameters[0], base_)) return false;
    std::copy(base_.begin(), base_.end(), residuals);
    if (jacobians == nullptr || jacobians[0] == nullptr) return true;
    if (!fit_jacobian(problem_, parameters[0], box_.lower, box_.upper, box_.step, base_,
                      columns_)) {
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

FitCovariance fit_covariance(const FitProblem& problem, const std::vector<double>& u,
                             const FitBox& box) {
  const std::size_t count = u.size();
  FitCovariance out;
  out.ci95.assign(count, std::numeric_limits<double>::infinity());
  out.no_influence.assign(count, false);
  out.correlation.assign(count, std::vector<double>(count, std::nan("")));
  std::vector<double> residuals, columns;
  if (!fit_residuals(problem, u.data(), residuals) ||
      !fit_jacobian(problem, u.data(), box.lower, box.upper, box.step, residuals, columns)) {
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
