// The least-squares problem of `stickslip fit` (private to the run wing): the map from the
// solver's scaled unknowns to the seat's parameters, and the residual of one exact simulation.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/fit.hpp"
#include "stickslip/host/run/simulation.hpp"

namespace stickslip::host {

// Unknown u_i of the solver, all of order 1: parameter = scale_i * u_i, except F_fs when F_fk is
// fitted too, which is F_fk + scale_i * u_i (the static excess), so that the box bound u_i >= 0
// keeps F_fs >= F_fk, as configure() requires.
struct FitProblem {
  const RigRecording* rig = nullptr;
  OscillatorParams base;  // dt_s, model and every parameter not fitted
  std::vector<FitParameter> order;
  std::vector<double> scale;
  bool static_excess = false;
  double travel_weight = 0.0;  // a_x noise / travel noise: the travel residual in a_x's units
};

// The parameters at u (u has order.size() entries).
OscillatorParams fit_params(const FitProblem& problem, const double* u);

// The physical value of each fitted parameter at u, in `order`.
std::vector<double> fit_values(const FitProblem& problem, const double* u);

// d value_i / d u_j of fit_values (a constant matrix: the map is linear), row-major.
std::vector<double> fit_value_jacobian(const FitProblem& problem);

// Residuals measured - model: a_x for every sample, then (with travel) travel_weight * x_r.
std::size_t fit_residual_count(const FitProblem& problem);

// What one model run writes, kept from one run to the next: a fit runs the model on the whole
// recording thousands of times, and buffers of that size taken afresh each time are mapped and
// returned to the kernel each time (under AddressSanitizer that took longer than the runs).
struct FitBuffers {
  SimulationTrace<double> run;      // the last model run, every part of the recording
  SimulationTrace<double> part;     // one part of a recording cut at its gaps
  std::vector<double> part_a_u;     // its input
  std::vector<double> residuals;    // fit_cost()'s
  std::vector<double> plus, minus;  // fit_jacobian()'s one-sided runs
};

// Simulates the recording at u into buffers.run; false if configure() refuses the parameters.
// `summary` (optional) receives the run's statistics.
bool fit_residuals(const FitProblem& problem, const double* u, std::vector<double>& residuals,
                   FitBuffers& buffers, SimulationSummary* summary = nullptr);

// The sum of squared residuals at u; infinity if configure() refuses the parameters.
double fit_cost(const FitProblem& problem, const double* u, FitBuffers& buffers);

// Why configure() refuses the parameters at u (its message, naming the parameter); empty if it
// accepts them.
std::string fit_refusal(const FitProblem& problem, const double* u);

// The Jacobian of fit_residuals at u, column-major (one column of residual_count per unknown), by
// central differences with step `step` in u. Per sample, where the two one-sided differences
// disagree (a stick, break-away or reversal crossed the sample between u and u +- step) the
// smaller one is taken: the derivative of the smooth piece the sample is on. A side beyond the
// bounds uses the other one alone. Returns false if no model run succeeds.
bool fit_jacobian(const FitProblem& problem, const double* u, const std::vector<double>& lower,
                  const std::vector<double>& upper, double step, const std::vector<double>& base,
                  std::vector<double>& jacobian, FitBuffers& buffers);

}  // namespace stickslip::host
