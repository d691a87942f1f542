// The accuracy target: stick-slip with in-step events at dt = 1 ms on a 120 s lorry recording from
// `generate` is within 0.1 % in T_ax and 0.005 in p of the same model at dt = 1e-5 s. The fine
// run sees the identical input (the linear interpolation of the 1 ms samples is exactly the
// first-order hold both runs assume), so any difference is the coarse step's own error.
#include <cmath>
#include <cstdio>
#include <vector>

#include "stickslip/host/run/simulation.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

using namespace stickslip;
using namespace stickslip::host;

namespace {

struct Figures {
  double transmissibility;
  double stick_probability;
  std::uint64_t events;
};

Figures run_stick_slip(const std::vector<double>& a_u, double dt_s, double friction_n) {
  SimulationSetup setup;
  setup.params.model = FrictionModel::stick_slip;
  setup.params.integrator = Integrator::exact;
  setup.params.kinetic_friction_n = friction_n;
  setup.params.static_friction_n = friction_n;
  setup.params.dt_s = dt_s;
  setup.repetitions = 1;
  SimulationTrace<double> trace;
  const SimulationSummary s = simulate_signal(setup, a_u, trace);
  CHECK_EQUAL(0u, s.event_budget_exhausted);
  return {s.transmissibility, s.stick_probability, s.events};
}

std::vector<double> refine_linearly(const std::vector<double>& coarse, int ratio) {
  std::vector<double> fine((coarse.size() - 1) * ratio + 1);
  for (std::size_t n = 0; n + 1 < coarse.size(); ++n) {
    for (int j = 0; j < ratio; ++j) {
      const double w = static_cast<double>(j) / ratio;
      fine[n * ratio + j] = (1.0 - w) * coarse[n] + w * coarse[n + 1];
    }
  }
  fine.back() = coarse.back();
  return fine;
}

}  // namespace

TEST_GROUP(StickSlipEventAccuracy){};

TEST(StickSlipEventAccuracy, OneMillisecondMatchesTenMicrosecondsOnGeneratedLorry) {
  GeneratorSpec spec;
  spec.kind = SignalKind::lorry;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = 120.0;
  spec.dt_s = 1e-3;
  spec.seed = 1;
  const std::vector<double> coarse = generate_signal(spec);
  const int ratio = 100;  // 1e-5 s
  const std::vector<double> fine = refine_linearly(coarse, ratio);
  // K = 1.31 (sticks ~3/4 of the time) and K = 0.44 (transition): both regimes.
  for (double friction_n : {45.0, 15.0}) {
    const Figures c = run_stick_slip(coarse, 1e-3, friction_n);
    const Figures f = run_stick_slip(fine, 1e-5, friction_n);
    const double t_ax_error = std::fabs(c.transmissibility / f.transmissibility - 1.0);
    const double p_error = std::fabs(c.stick_probability - f.stick_probability);
    std::printf(
        "\n  F_fk %g N: T_ax %.6f vs %.6f (rel %.2e), p %.6f vs %.6f (abs %.2e), events %llu",
        friction_n, c.transmissibility, f.transmissibility, t_ax_error, c.stick_probability,
        f.stick_probability, p_error, static_cast<unsigned long long>(c.events));
    CHECK(c.events > 100);  // the scene really sticks and slips
    CHECK(t_ax_error < 1e-3);
    CHECK(p_error < 0.005);
  }
}
