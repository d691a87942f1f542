// Recordings onto the model's time step: irregular sample times onto a uniform grid (natural
// cubic spline through the samples), and a uniform recording from one rate to another (libsoxr,
// very high quality). docs/RECORDINGS.md states the methods and their measured error.
#pragma once

#include <cstddef>
#include <vector>

namespace stickslip::host {

// The values of the natural cubic spline through (t_s[i], values[i]) at t0_s + k step_s,
// k = 0..count-1. t_s must increase strictly, have the same length as values (>= 2), and the grid
// must start within [t_s.front(), t_s.back()]; a grid point past the last sample (by rounding)
// is evaluated at the last sample.
std::vector<double> spline_onto_grid(const std::vector<double>& t_s,
                                     const std::vector<double>& values, double t0_s, double step_s,
                                     std::size_t count);

// `values` sampled at in_rate_hz converted to out_rate_hz with libsoxr's very high quality
// (SOXR_VHQ: linear phase, pass band to 0.95 of the lower Nyquist frequency, 175 dB stop-band
// rejection), its delay removed so that output k is at time k / out_rate_hz from the same
// origin. The record is continued past both ends by odd reflection before filtering, so a
// constant or a ramp comes out unchanged up to its first and last sample; where out/in is no
// ratio of small integers the start is continued by its value only (a constant still exact).
// Returns min(out_count, what soxr delivers) samples; throws HostError if soxr fails.
std::vector<double> resample_rate(const std::vector<double>& values, double in_rate_hz,
                                  double out_rate_hz, std::size_t out_count);

// A uniform recording at step_s onto new_step_s over the same span, by resample_rate(): the
// samples at k new_step_s from the first that fall within the span (to a millionth of a step, so
// that a span that is a whole number of new steps only to rounding keeps its last sample).
std::vector<double> resample_step(const std::vector<double>& values, double step_s,
                                  double new_step_s);

}  // namespace stickslip::host
