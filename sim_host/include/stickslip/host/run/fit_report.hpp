// What `stickslip fit` prints and draws: the estimates with their intervals and the diagnostics
// as lines for a person, the JSON line for tools, and the residual plot (gnuplot, PNG).
#pragma once

#include <string>

#include "stickslip/host/io/rig_recording.hpp"
#include "stickslip/host/run/fit.hpp"
#include "stickslip/host/run/gnuplot_png.hpp"

namespace stickslip::host {

// The estimates (value +- 95 % half-width, unit), residual RMS against the noise estimate, T_ax
// and p measured and fitted, the correlations, the warnings; one line each, '\n'-terminated.
std::string fit_report_text(const FitResult& result);

// One line, no newline: the fitted parameters' values and <key>_ci95 (null where unbounded),
// rms_residual, T_ax_measured, T_ax_model, p_measured, p_model, condition_number, iterations,
// seconds, converged.
std::string fit_json(const FitResult& result);

// Residual a_x (measured - model) against t, as a PNG written by gnuplot under a temporary name
// and renamed into place; throws HostError (nothing left behind) if gnuplot fails.
void write_residual_plot(const RigRecording& rig, const FitResult& result,
                         const std::string& png_path);

}  // namespace stickslip::host
