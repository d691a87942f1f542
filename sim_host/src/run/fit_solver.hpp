// The local solver of `stickslip fit` (private to the run wing): Ceres Solver's
// Levenberg-Marquardt on a FitProblem, and the Gauss-Newton covariance at its solution. The only
// file that includes Ceres and Eigen, so that their heavy headers compile once.
#pragma once

#include <string>
#include <vector>

#include "fit_problem.hpp"

namespace stickslip::host {

// Box bounds on the unknowns u, and the finite-difference steps in u.
struct FitBox {
  std::vector<double> lower, upper;
  // Levenberg-Marquardt's Jacobian: a secant over many treads of the staircase (pattern_search).
  double step = 1e-3;
  // The intervals' Jacobian, the derivative of the smooth piece the fit ended on. A step of 1e-3
  // moves dozens of events across samples; where a moved stick or break-away changes the motion
  // for a long run of samples on both sides, the per-sample rule of fit_jacobian() cannot pick a
  // smooth side and a column blows up: at K = 1.5 the F_fk interval of 3 of 12 validation fits
  // came out 3-12 times narrower than the others' (0.005-0.020 % against 0.06 %) and missed the
  // truth. At 1e-5 they agree with the rest (0.060-0.068 %); the differences still lie far above
  // rounding (a_x to about 1e-15 m/s^2, so about 1e-10 against sensitivities of 0.01-1).
  double covariance_step = 1e-5;
};

struct LocalFit {
  std::vector<double> u;
  double cost = 0.0;  // sum of squared residuals
  int iterations = 0;
  bool converged = false;
  std::string message;
};

// Starts at u0; a model run that configure() refuses is a step the trust region rejects.
LocalFit solve_local(const FitProblem& problem, const FitBox& box, std::vector<double> u0,
                     int max_iterations);

// The principal axes of the Gauss-Newton covariance s^2 (J'J)^-1 at u (s^2 = cost / (N - P)),
// each scaled to one standard error; empty if the model refuses u. Adds the model runs it took
// to `evaluations`.
std::vector<std::vector<double>> principal_axes(const FitProblem& problem, const FitBox& box,
                                                const std::vector<double>& u, double cost,
                                                FitBuffers& buffers, int* evaluations = nullptr);

// A derivative-free descent on the exact cost from `start`, for what Levenberg-Marquardt cannot
// see: a sample's a_x jumps where a stick or break-away crosses it, so near the minimum the cost
// is a staircase of plateaus far narrower than the intervals (a move of 0.1-0.2 standard errors
// in the parameters can change the residual RMS by 0.5-1 %), and the Jacobian of the smooth
// pieces sees a flat tread. A compass search (Kolda, Lewis & Torczon, SIAM Review 45, 2003) along
// the principal axes of the Gauss-Newton covariance at `start`: steps of `first_step` standard
// errors along each axis both ways, a success repeated with the step doubled, no success halves the
// step, down to `last_step` or `max_evaluations` model runs. With `diagonals` the pattern also
// holds every signed combination of two or more axes, sum c_i a_i / sqrt(#c_i != 0) with c_i in
// {-1, 0, 1} (3^n - 1 points per step for n unknowns; fit.cpp, escape()). Every point it accepts
// has a lower cost.
struct PatternSearch {
  std::vector<double> u;
  double cost = 0.0;
  int evaluations = 0;
  int moves = 0;  // accepted points
};
PatternSearch pattern_search(const FitProblem& problem, const FitBox& box,
                             const std::vector<double>& start, double start_cost, double first_step,
                             double last_step, int max_evaluations, bool diagonals = false);

struct FitCovariance {
  // Of fit_values(), in `order`; a parameter with no influence on the residuals has
  // ci95 = infinity and is left out of the correlations (NaN there).
  std::vector<double> ci95;
  std::vector<std::vector<double>> correlation;
  double condition_number = 0.0;  // of J'J scaled to a unit diagonal (the unknowns' correlation)
  std::vector<bool> no_influence;
  // The same intervals from the heteroskedasticity- and autocorrelation-consistent (sandwich)
  // covariance (J'J)^-1 S (J'J)^-1, S the Newey-West (Bartlett) estimate of the scores'
  // long-run covariance with Andrews' AR(1) plug-in lag: what the intervals become when the
  // residuals are not white.
  std::vector<double> ci95_hac;
  int hac_lag = 0;                         // samples
  double residual_lag1_correlation = 0.0;  // of the residuals at the solution
};

// s^2 (J'J)^-1 with s^2 = SSR / (N - P), mapped to the parameters; 95 % = 1.96 standard errors.
FitCovariance fit_covariance(const FitProblem& problem, const std::vector<double>& u,
                             const FitBox& box);

}  // namespace stickslip::host
