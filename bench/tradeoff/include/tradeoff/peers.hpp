// The peers: the same scenes solved the way a user would without this library, with Boost.Odeint
// (fixed-step runge_kutta4 and controlled runge_kutta_dopri5 on the smoothed signum, and dopri5
// with event bisection on stick-slip), measured with the same streaming loop and statistics.
#pragma once

#include <vector>

#include "stickslip/core/params.hpp"
#include "tradeoff/combinations.hpp"
#include "tradeoff/measure.hpp"
#include "tradeoff/reference.hpp"

namespace stickslip::tradeoff {

// Event bisection stops when the bracket is shorter than this many seconds per unit of tolerance
// (tolerance 1e-6 -> 1e-9 s).
inline constexpr double kPeerEventTimeTolerancePerTolerance = 1e-3;
// Events per sample interval before the events peer stops looking (keeps degenerate chattering
// at a break-away bounded; counted in the note).
inline constexpr int kPeerMaxEventsPerSample = 32;

// `scene_params` is the Coulomb scene's physics at the run's dt (F_fk, F_fs, m, k, b, dt_s, c).
Outcome run_peer(const PeerSpec& peer, const OscillatorParams& scene_params,
                 const std::vector<double>& a_u, const Reference& physics, const Timing& timing);

}  // namespace stickslip::tradeoff
