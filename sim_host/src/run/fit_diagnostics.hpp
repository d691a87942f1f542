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

// How many samples lie in stuck phases (runs of kStuckPhaseSamples or more within
// stuck_threshold_m_per_s2()) with a_x shifted by each lag against a_u: where the seat sticks,
// a_x equals a_u, whatever the model; the brief matches where a_x - a_u crosses zero are not
// phases. `counts` holds the lags -reach .. reach.
struct StuckLags {
  long reach = 0;
  std::vector<std::size_t> counts;
  std::size_t at(long lag) const { return counts[static_cast<std::size_t>(lag + reach)]; }
  long best() const;  // the lag with the most; the one nearest 0 on a tie
};
StuckLags stuck_lags(const RigRecording& rig, const RigInspection& data);

// Throws HostError "FILE: a_x is shifted ..." when a_x lags or leads a_u by 3 samples and 3 ms
// or more: a delay is nothing a seat model can reproduce, so the estimates would be wrong.
// check_stuck_alignment(), before any model runs: where the recording shows stuck phases, their
// shift decides (returns true: aligned), so a model that does not fit the seat (another law) is
// not mistaken for a shift; false when there are none to tell. check_model_alignment(), for a
// recording without them: the lag at which the fitted model's a_x matches the measured one best.
bool check_stuck_alignment(const RigRecording& rig, const RigInspection& data);
void check_model_alignment(const RigRecording& rig, const std::vector<double>& model_a_x);

// Identifiability, bounds reached and poorly determined parameters, one sentence each.
std::vector<std::string> fit_warnings(const FitResult& result, const FitCovariance& covariance,
                                      const RigInspection& data, const FitBox& box,
                                      const std::vector<double>& u);

}  // namespace stickslip::host
