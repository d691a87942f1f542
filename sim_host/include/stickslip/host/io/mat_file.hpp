// MATLAB recordings (.mat, level 5 or 7.3 as libmatio reads them) as simulate inputs.
//
// The file holds a numeric vector `a_u` (m/s^2) and either a vector `t` (s, increasing, same
// length) or a scalar `dt` (s; t = n dt). Any real numeric class is accepted and converted to
// double. Problems are HostErrors naming the file and the variable.
#pragma once

#include <string>
#include <vector>

#include "stickslip/host/io/csv_reader.hpp"

namespace stickslip::host {

// What `t` must be: uniform (the model's own input, as a t,a_u CSV), or only increasing (a
// logger's jittered or gapped times, which the recording options then put on a uniform grid;
// dt_s is then the mean step).
enum class MatTimes { uniform, increasing };

SampledSignal read_signal_mat(const std::string& path, MatTimes times = MatTimes::uniform);

// Writes `t` and `a_u` as double column vectors in a MATLAB level-5 file (for tests and users).
void write_signal_mat(const std::string& path, const SampledSignal& signal);

// By extension: ".mat" (any case) through read_signal_mat, anything else as CSV.
SampledSignal read_signal_file(const std::string& path);

}  // namespace stickslip::host
