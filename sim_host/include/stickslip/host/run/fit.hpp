// `stickslip fit`: identifies the seat (k, b, F_fk, F_fs, v_S; m given) from a rig recording
// by nonlinear least squares on the a_x residual (and the travel residual when x_r is recorded).
// Every model evaluation is the exact simulation of the whole recording (simulate_signal(), the
// core's oscillator with the exact integrator, from rest); Ceres Solver's Levenberg-Marquardt
// minimises the sum of squares, with the Jacobian by central finite differences that step over no
// mode change (docs/IDENTIFICATION.md, "Fitting a seat", says why); a derivative-free compass
// search then descends the staircase that the stick and break-away samples make of the cost near
// its minimum, which the Jacobian does not see. Confidence intervals come from the Gauss-Newton
// covariance s^2 (J'J)^-1 with the residual variance s^2 = SSR / (N - P), at the final point.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "stickslip/core/params.hpp"
#include "stickslip/host/io/rig_recording.hpp"

namespace stickslip::host {

// The parameters a fit can estimate, in the order of the JSON keys.
enum class FitParameter : std::size_t {
  mass,
  stiffness,
  damping,
  ffk,
  ffs,
  stribeck_velocity,
};
inline constexpr std::size_t kFitParameterCount = 6;

const char* fit_parameter_name(FitParameter parameter) noexcept;  // "stiffness", "ffk", ...
const char* fit_parameter_unit(FitParameter parameter) noexcept;  // "N/m", ...
bool parse_fit_parameter(const std::string& name, FitParameter& out) noexcept;

struct FitRequest {
  FrictionModel model = FrictionModel::stick_slip;
  double mass_kg = 0.0;  // known mass (fit[mass] is refused: the motion fixes only k/m, b/m, F/m)
  // Which parameters to estimate; the others keep `fixed` (mass: mass_kg).
  std::array<bool, kFitParameterCount> fit{};
  // Start values (0: automatic, from the data) and bounds (0: automatic), SI units.
  std::array<double, kFitParameterCount> start{};
  std::array<double, kFitParameterCount> lower{};
  std::array<double, kFitParameterCount> upper{};
  // Values of parameters not fitted (F_fs of a Stribeck law fitted only in F_fk, ...).
  OscillatorParams fixed;
  double travel_noise_m = 1e-4;  // weight of the travel residual against a_x's noise
  int max_iterations = 100;
};

// One part of a recording cut at its gaps (--gaps split), each simulated from rest at its start.
struct FitSegment {
  double t_start_s = 0.0;
  std::size_t samples = 0;
  double rms_residual_m_per_s2 = 0.0;  // a_x
};

struct FitResult {
  std::array<bool, kFitParameterCount> fitted{};
  std::array<double, kFitParameterCount> value{};  // SI; fixed ones as given
  std::array<double, kFitParameterCount> ci95{};   // half-width of the 95 % interval
  std::array<double, kFitParameterCount> start{};  // where the local solver started
  // The sandwich (HAC) interval of the same fit (fit_solver.hpp), for the validation's comparison.
  std::array<double, kFitParameterCount> ci95_hac{};
  int hac_lag = 0;
  double residual_lag1_correlation = 0.0;
  std::vector<FitParameter> order;               // the fitted ones, in order
  std::vector<std::vector<double>> correlation;  // of `order`
  double condition_number = 0.0;                 // of the scaled J'J
  double rms_residual_m_per_s2 = 0.0;            // a_x
  double rms_travel_residual_m = 0.0;            // x_r (0 without travel)
  double transmissibility_measured = 0.0, transmissibility_model = 0.0;
  double stick_probability_measured = 0.0, stick_probability_model = 0.0;
  double noise_m_per_s2 = 0.0;  // a_x's white-noise RMS estimated from the data
  int iterations = 0;
  int starts = 0;              // model runs of the global stage
  int local_runs = 0;          // local solver runs (Levenberg-Marquardt and polish)
  int search_evaluations = 0;  // model runs of the derivative-free descent (fit_solver.hpp)
  double seconds = 0.0;
  bool converged = false;
  std::string solver_message;             // Ceres' reason for stopping
  std::vector<std::string> warnings;      // identifiability, lag, bounds reached
  std::vector<double> residual_m_per_s2;  // measured - model a_x, per sample
  std::vector<FitSegment> segments;       // a recording split at gaps: each part; else empty
  OscillatorParams params;                // the fitted seat
};

// Checks the recording (plausible units, channels aligned against the fitted model) and fits.
// Throws HostError for data that cannot be fitted (one line naming the file and the problem) and
// UsageError for a request that makes no sense (the mass fitted, a parameter the model does not
// have). A fit that stops without converging returns converged = false.
FitResult fit_seat(const RigRecording& rig, const FitRequest& request);

// The fit's cost and Gauss-Newton intervals at given parameters, without fitting: at the true
// parameters of a synthetic rig the residual RMS is the floor any fit should reach, and
// ci95 * noise / rms_residual is 1.96 times the Cramer-Rao bound of each fitted parameter (the
// Fisher information J'J / noise^2 with the Jacobian at the truth, white Gaussian noise).
struct FitProbe {
  std::array<double, kFitParameterCount> ci95{};  // s^2 (J'J)^-1, s^2 = SSR / (N - P)
  double rms_residual_m_per_s2 = 0.0;             // a_x
  double rms_travel_residual_m = 0.0;             // x_r (0 without travel)
};
FitProbe probe_fit(const RigRecording& rig, const FitRequest& request,
                   const OscillatorParams& point);

}  // namespace stickslip::host
