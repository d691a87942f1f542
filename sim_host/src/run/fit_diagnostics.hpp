// What `stickslip fit` says about its own result (private to the run wing): whether a_x is
// shifted against a_u, and which parameters this recording cannot tell apart.
#pragma once

#include <string>
#include <vector>

#include "fit_solver.hpp"
#include "fit_start.hpp"
#include "stickslip/host/run/fit.hpp"

namespace stickslip::host {

// The lag (samples, positive: a_x late) at which the measured a_x correlates best with the
// model's, over +-250 ms.
long best_lag_samples(const std::vector<double>& measured, const std::vector<double>& model,
                      double dt_s);

// Throws HostError "FILE: a_x is shifted ..." when the lag is 3 samples and 3 ms or more: a
// delay is nothing a seat model can reproduce, so the estimates would be wrong.
void check_alignment(const RigRecording& rig, const std::vector<double>& model_a_x);

// Identifiability, bounds reached and poorly determined parameters, one sentence each.
std::vector<std::string> fit_warnings(const FitResult& result, const FitCovariance& covariance,
                                      const RigInspection& data, const FitBox& box,
                                      const std::vector<double>& u);

}  // namespace stickslip::host
