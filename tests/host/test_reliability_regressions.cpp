// Scenes at the edge of what the float step handles, from the stability map (reliability/,
// docs/STABILITY.md), on the exact input that exposes them: the trade-off bench's lorry-like
// scene.
#include <cmath>
#include <cstddef>
#include <vector>

#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/models/oscillator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;

TEST_GROUP(ReliabilityRegressions){};

// Float Stribeck (K = 0.8, b = 504 N s/m, F_fs = 1.3 F_fk, v_S = 0.01 m/s) with euler at 0.1 ms and
// symplectic at 0.25 ms: at a break-away with |F_L| ~ F_fs the float rounding of v_r over a
// block started at rest can fake a crossing per tick and spend every event of a step's
// budget. No step may exhaust it, and the run must stay finite.
TEST(ReliabilityRegressions, FloatStribeckBreakAwayAtTheLimitKeepsTheEventBudget) {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::lorry;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = 20.0;
  spec.dt_s = 5e-5;
  spec.seed = 1;
  const std::vector<double> base = host::generate_signal(spec);
  struct Case {
    Integrator integrator;
    std::size_t stride;  // dt / 0.05 ms
  };
  for (const Case c : {Case{Integrator::euler, 2}, Case{Integrator::symplectic, 5}}) {
    OscillatorParams p;
    p.model = FrictionModel::stribeck;
    p.integrator = c.integrator;
    p.dt_s = spec.dt_s * static_cast<double>(c.stride);
    p.damping_ns_per_m = 504.0;
    p.kinetic_friction_n = 0.8 * 3.14159265358979323846 * std::sqrt(2.0) * p.mass_kg * 0.35 / 4.0;
    p.static_friction_n = 1.3 * p.kinetic_friction_n;
    p.stribeck_velocity_m_per_s = 0.01;
    Oscillator<float, StribeckStickSlip> seat;
    CHECK(seat.configure(p).ok());
    seat.reset(0.0f, 0.0f, static_cast<float>(base[0]));
    int events = 0, stuck = 0;
    bool finite = true;
    for (std::size_t n = c.stride; n < base.size(); n += c.stride) {
      const auto out = seat.step(static_cast<float>(base[n]));
      events += out.events;
      stuck += out.stuck ? 1 : 0;
      finite = finite && std::isfinite(out.x_r_m) && std::isfinite(out.a_x_m_per_s2);
    }
    CHECK_TEXT(seat.event_budget_exhausted() == 0, integrator_name(c.integrator));
    CHECK(finite);
    CHECK(seat.state_resets() == 0);
    CHECK(events > 100 && stuck > 1000);  // the scene does stick and break away many times
  }
}
