// A seat-rig recording for identification: the cab-floor acceleration a_u, the seat acceleration
// a_x (both m/s^2) and optionally the measured travel x_r (m), on a uniform time base t (s).
// Read from any delimited text table read_delimited_text() accepts (CSV, logger exports), with
// the columns found by name; a unit written in the header must be the SI one (an acceleration in
// g is refused with the factor to convert, never converted silently).
#pragma once

#include <cstddef>
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
  // The first sample of each part of a recording cut at its gaps (--gaps split), the parts laid
  // end to end in the vectors above; empty: one part. The fit runs each part alone.
  std::vector<std::size_t> segment_starts;
  bool has_travel() const noexcept { return !x_r_m.empty(); }
  std::size_t segment_count() const noexcept {
    return segment_starts.empty() ? 1 : segment_starts.size();
  }
  // [begin, end) of part i.
  std::size_t segment_begin(std::size_t i) const noexcept {
    return segment_starts.empty() ? 0 : segment_starts[i];
  }
  std::size_t segment_end(std::size_t i) const noexcept {
    return i + 1 < segment_starts.size() ? segment_starts[i + 1] : t_s.size();
  }
};

// Throws HostError "FILE: problem" for a missing column (a_x is named as the seat acceleration
// the fit needs), a unit other than SI, fewer than 16 samples, or a non-uniform t.
RigRecording read_rig_recording(const std::string& path);

}  // namespace stickslip::host
