// PNG plots drawn by gnuplot (fit's residuals, closed-loop's Pareto front): one place for running
// it, reporting its failure and leaving nothing half-written.
#pragma once

#include <string>

namespace stickslip::host {

// Whether a `gnuplot` executable is on PATH.
bool gnuplot_available();

// Runs `script`, which reads `data_path` and writes `image_path` (both temporary), then removes
// the data and renames the image to `png_path`. On failure removes both temporaries and throws a
// HostError naming `png_path`, `what` ("the residual plot") and gnuplot's first line.
void draw_png(const std::string& script, const std::string& data_path,
              const std::string& image_path, const std::string& png_path, const char* what);

}  // namespace stickslip::host
