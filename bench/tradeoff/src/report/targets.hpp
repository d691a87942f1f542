// The performance targets the report judges, and the configuration that carries the headline
// figures.
#pragma once

namespace stickslip::tradeoff::report {

inline constexpr double kTargetNsPerSample = 10.0;  // stick-slip, exact, double, streaming
inline constexpr double kTargetTaxRelErr = 1e-3;    // at dt = 1 ms on the lorry-like scene
inline constexpr double kTargetPAbsErr = 0.005;
inline constexpr double kTargetPeerRatio =
    50.0;  // vs the fastest peer reaching the same T_ax error
inline constexpr double kTargetBatchSpeedup = 4.0;
inline constexpr double kHeadlineDtMs = 1.0;
inline constexpr const char* kHeadlineScene = "lorry-K0.8-b504";

// Relative T_ax error bands of the summaries.
inline constexpr double kBands[] = {1e-1, 1e-2, 1e-3, 1e-4};
// Runs whose median costs differ by less than this are ties (the timing noise of this machine);
// the recommendation then takes the more accurate one.
inline constexpr double kCostTie = 1.10;

}  // namespace stickslip::tradeoff::report
