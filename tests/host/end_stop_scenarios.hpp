// The inputs and seats the end-stop tests share (test_end_stop_exactness.cpp,
// test_end_stop_actuator.cpp): a seeded wide-band floor at 1 ms, the reference seat with a chosen
// friction and damping, and stops of 2e5 N/m at a chosen travel.
#pragma once

#include <cstdint>
#include <vector>

#include "../core/oracles.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/end_stops.hpp"

namespace stickslip::test::end_stop {

constexpr double kDt = 1e-3;

inline std::vector<double> wideband(double rms, double duration_s, std::uint64_t seed) {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::wideband;
  spec.rms_m_per_s2 = rms;
  spec.duration_s = duration_s;
  spec.dt_s = kDt;
  spec.seed = seed;
  return host::generate_signal(spec);
}

inline OscillatorParams seat(FrictionModel model, double damping, double kinetic_n,
                             double static_n) {
  OscillatorParams p = reference_params(model, Integrator::exact, kDt, damping);
  p.kinetic_friction_n = kinetic_n;
  p.static_friction_n = static_n;
  return p;
}

inline EndStopParams stops(double travel_m, double damping) {
  EndStopParams s;
  s.travel_m = travel_m;
  s.stiffness_n_per_m = 2.0e5;
  s.damping_ns_per_m = damping;
  return s;
}

}  // namespace stickslip::test::end_stop
