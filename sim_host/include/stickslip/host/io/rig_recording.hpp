// A seat-rig recording for identification: the cab-floor acceleration a_u, the seat acceleration
// a_x (both m/s^2) and optionally the measured travel x_r (m), on a uniform time base t (s).
// Read from any delimited text table read_delimited_text() accepts (CSV, logger exports), with
// the columns found by name; a unit written in the header must be the SI one (an acceleration in
// g is refused with the factor to convert, never converted silently).
#pragma once

#include <string>
#include <vector>

namespace stickslip::host {

struct RigRecording {
  std::string path;
  std::vector<double> t_s;
  std::vector<double> a_u_m_per_s2;
  std::vector<double> a_x_m_per_s2;
  std::vector<double> x_r_m;  // empty when the recording has no travel column
  double dt_s = 0.0;
  bool has_travel() const noexcept { return !x_r_m.empty(); }
};

// Throws HostError "FILE: problem" for a missing column (a_x is named as the seat acceleration
// the fit needs), a unit other than SI, fewer than 16 samples, or a non-uniform t.
RigRecording read_rig_recording(const std::string& path);

}  // namespace stickslip::host
