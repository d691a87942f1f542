#include "fit_start.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "stickslip/host/error.hpp"
#include "stickslip/host/signals/welch.hpp"

namespace stickslip::host {
namespace {

constexpr double kStandardGravity_m_per_s2 = 9.80665;

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

double rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (double value : values) sum += value * value;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

// White noise of RMS s has second differences of RMS s sqrt(6); a signal band-limited well below
// the sample rate adds little to them, and the median ignores the jumps at stick and break-away.
double white_noise_rms(const std::vector<double>& signal) {
  std::vector<double> second(signal.size() - 2);
  for (std::size_t n = 0; n + 2 < signal.size(); ++n)
    second[n] = std::fabs(signal[n + 2] - 2.0 * signal[n + 1] + signal[n]);
  return median(std::move(second)) / 0.6744897501960817 / std::sqrt(6.0);
}

void find_stuck_phases(const RigRecording& rig, RigInspection& out) {
  const std::size_t count = rig.a_u_m_per_s2.size();
  mark_stuck(rig.a_x_m_per_s2.data(), rig.a_u_m_per_s2.data(), count, stuck_threshold_m_per_s2(out),
             out.stuck);
  std::size_t stuck_samples = 0, start = 0;
  for (std::size_t n = 0; n <= count; ++n) {
    const bool stuck = n < count && out.stuck[n] != 0;
    if (stuck) {
      if (n == 0 || out.stuck[n - 1] == 0) start = n;
      ++stuck_samples;
      continue;
    }
    if (n == 0 || out.stuck[n - 1] == 0 || n - start < kStuckPhaseSamples) continue;
    ++out.stuck_phases;
    const auto first = rig.a_u_m_per_s2.begin() + static_cast<std::ptrdiff_t>(start);
    const auto last = rig.a_u_m_per_s2.begin() + static_cast<std::ptrdiff_t>(n);
    const auto [low, high] = std::minmax_element(first, last);
    out.static_force_bound_per_kg = std::max(out.static_force_bound_per_kg, 0.5 * (*high - *low));
  }
  out.stuck_share = static_cast<double>(stuck_samples) / static_cast<double>(count);
}

void measure_transfer(const RigRecording& rig, RigInspection& out) {
  std::size_t segment = 8;
  while (segment * 2 <= rig.a_u_m_per_s2.size() / 4 && segment < (std::size_t{1} << 15))
    segment *= 2;
  if (segment * 4 > rig.a_u_m_per_s2.size()) return;
  const Spectrum floor = welch_psd(rig.a_u_m_per_s2, rig.dt_s, segment);
  const Spectrum seat = welch_psd(rig.a_x_m_per_s2, rig.dt_s, segment);
  const double top_hz = std::min(15.0, 0.4 / rig.dt_s);
  for (std::size_t k = 1; k < floor.psd.size(); ++k) {
    const double f = floor.frequency_hz[k];
    if (f < 0.3 || f > top_hz || !(floor.psd[k] > 0.0)) continue;
    const double gain = std::sqrt(seat.psd[k] / floor.psd[k]);
    if (gain > out.peak_gain) {
      out.peak_gain = gain;
      out.peak_hz = f;
    }
  }
  // Only where the floor moves: a bin that holds little of the floor's power (a harmonic or
  // narrow-band floor) holds leakage and noise, whose ratio says nothing of the units.
  double floor_peak = 0.0;
  for (std::size_t k = 1; k < floor.psd.size(); ++k)
    if (floor.frequency_hz[k] <= top_hz) floor_peak = std::max(floor_peak, floor.psd[k]);
  std::vector<double> low;
  for (std::size_t k = 1; k < floor.psd.size(); ++k) {
    const double f = floor.frequency_hz[k];
    if (f >= 0.15 * out.peak_hz && f <= 0.5 * out.peak_hz && floor.psd[k] > 1e-4 * floor_peak)
      low.push_back(std::sqrt(seat.psd[k] / floor.psd[k]));
  }
  if (low.size() >= 3) out.low_frequency_gain = median(std::move(low));
}

void check_units(const RigRecording& rig, const RigInspection& out) {
  const double gain = out.low_frequency_gain;
  if (gain == 0.0 || (gain > 0.5 && gain < 2.0)) return;
  const double g = kStandardGravity_m_per_s2;
  if (gain > 0.5 / g && gain < 2.0 / g) {
    throw HostError(fmt::format(
        "{}: a_x looks like it is in g, not m/s^2: |a_x/a_u| below the natural frequency is {:.3g} "
        "where a seat transmits about 1 (1/g = 0.102); multiply a_x by {}",
        rig.path, gain, g));
  }
  if (gain > 0.5 * g && gain < 2.0 * g) {
    throw HostError(fmt::format(
        "{}: a_u looks like it is in g, not m/s^2: |a_x/a_u| below the natural frequency is {:.3g} "
        "where a seat transmits about 1; multiply a_u by {}",
        rig.path, gain, g));
  }
  throw HostError(fmt::format(
      "{}: |a_x/a_u| below the natural frequency is {:.3g} where a seat transmits about 1: are "
      "both channels in m/s^2, and is a_x the seat and a_u the floor?",
      rig.path, gain));
}

}  // namespace

double stuck_threshold_m_per_s2(const RigInspection& data) {
  const double noise = std::hypot(data.a_x_noise_m_per_s2, data.a_u_noise_m_per_s2);
  return std::max(4.0 * noise / std::sqrt(static_cast<double>(kStuckFilterSamples)), 1e-9);
}

void mark_stuck(const double* a_x, const double* a_u, std::size_t count, double threshold_m_per_s2,
                std::vector<std::uint8_t>& stuck) {
  stuck.assign(count, 0);
  double sum = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    sum += a_x[n] - a_u[n];
    if (n >= kStuckFilterSamples)
      sum -= a_x[n - kStuckFilterSamples] - a_u[n - kStuckFilterSamples];
    const std::size_t width = std::min(n + 1, kStuckFilterSamples);
    if (std::fabs(sum) / static_cast<double>(width) < threshold_m_per_s2) stuck[n] = 1;
  }
}

RigInspection inspect_rig(const RigRecording& rig) {
  RigInspection out;
  out.a_x_noise_m_per_s2 = white_noise_rms(rig.a_x_m_per_s2);
  out.a_u_noise_m_per_s2 = white_noise_rms(rig.a_u_m_per_s2);
  out.rms_u_m_per_s2 = rms(rig.a_u_m_per_s2);
  out.rms_x_m_per_s2 = rms(rig.a_x_m_per_s2);
  if (!(out.rms_u_m_per_s2 > 0.0))
    throw HostError(rig.path + ": a_u is zero throughout: nothing excites the seat");
  measure_transfer(rig, out);
  check_units(rig, out);
  find_stuck_phases(rig, out);
  return out;
}

}  // namespace stickslip::host
