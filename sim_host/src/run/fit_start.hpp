// What `stickslip fit` reads from a rig recording before any model runs (private to the run
// wing): the sensor noise, the stuck phases, the transfer |a_x/a_u| over frequency, and from them
// the plausibility of the units and the automatic start.
#pragma once

#include <cstdint>
#include <vector>

#include "stickslip/host/io/rig_recording.hpp"

namespace stickslip::host {

struct RigInspection {
  double a_x_noise_m_per_s2 = 0.0;  // white-noise RMS, from second differences (median, robust)
  double a_u_noise_m_per_s2 = 0.0;
  double rms_u_m_per_s2 = 0.0, rms_x_m_per_s2 = 0.0;
  std::vector<std::uint8_t> stuck;  // per sample: the relative acceleration is noise only
  double stuck_share = 0.0;
  std::size_t stuck_phases = 0;            // runs of >= kStuckPhaseSamples stuck samples
  double static_force_bound_per_kg = 0.0;  // max over phases of (max a_u - min a_u) / 2
  double peak_hz = 0.0;                    // largest |a_x/a_u| between 0.3 and 15 Hz
  double peak_gain = 0.0;
  double low_frequency_gain = 0.0;  // median |a_x/a_u| over 0.15..0.5 peak_hz; 0: no such bins
};

inline constexpr std::size_t kStuckPhaseSamples = 20;
// The window over which a_x - a_u is averaged to tell a stuck sample: a stuck phase shows from
// its kStuckFilterSamples-th sample, shorter ones not at all.
inline constexpr std::size_t kStuckFilterSamples = 16;

// The bound on |a_x - a_u| averaged over kStuckFilterSamples below which a sample counts as stuck:
// 4 standard deviations of that average where the sensors' noise is all there is.
double stuck_threshold_m_per_s2(const RigInspection& data);

// Marks stuck[n] = 1 where a_x[n] - a_u[n], averaged over the last kStuckFilterSamples samples
// (fewer at the start), is within threshold of zero; stuck is resized to count. The one test of a
// stuck sample, for the unshifted channels and for a_x moved against a_u alike.
void mark_stuck(const double* a_x, const double* a_u, std::size_t count, double threshold_m_per_s2,
                std::vector<std::uint8_t>& stuck);

// Throws HostError "FILE: ..." when |a_x/a_u| below the natural frequency, where every seat
// transmits the floor's motion (gain about 1), says one channel is in other units (g: 0.102 or
// 9.8).
RigInspection inspect_rig(const RigRecording& rig);

}  // namespace stickslip::host
