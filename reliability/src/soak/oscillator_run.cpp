// --path oscillator: the oscillator and RunningStatistics only (the whole-stream checks, no
// observer).
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "soak/oracle.hpp"
#include "soak/report.hpp"
#include "soak/runner.hpp"
#include "soak/scene.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip::soak {

template <typename T>
int soak_oscillator(const Options& o) {
  const Scene<T> scene = lorry_scene<T>();
  const std::vector<T>& input = scene.input;
  const std::uint64_t period = input.size();
  const OscillatorParams& p = scene.params;
  Oscillator<T, CoulombStickSlip> seat;
  const auto config = seat.configure(p);
  if (!config.ok()) {
    std::fprintf(stderr, "soak: %s\n", config.message.c_str());
    return 1;
  }
  Report report(o);
  if (!report.open_csv(false)) {
    std::fprintf(stderr, "soak: cannot write %s\n", o.csv);
    return 2;
  }
  report.header(false);

  const double tolerance = 256.0 * static_cast<double>(std::numeric_limits<T>::epsilon());
  RunningStatistics<T> stats;
  stats.reset();
  seat.reset(T(0), T(0), input[0]);
  const T a_x0 = seat.current().a_x_m_per_s2;
  stats.add_sample(input[0], a_x0);
  WholeStreamReference whole;
  whole.add(static_cast<long double>(input[0]) * static_cast<long double>(input[0]),
            static_cast<long double>(a_x0) * static_cast<long double>(a_x0), 0);
  std::uint64_t non_finite = 0;
  const std::uint64_t every = o.samples / static_cast<std::uint64_t>(o.checkpoints);
  std::uint64_t next_checkpoint = every;
  std::uint64_t index = 0;  // into the looped recording
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t n = 1; n < o.samples; ++n) {  // time t = n dt: an integer, never accumulated
    if (++index == period) index = 0;
    const T a_u = input[index];
    const auto out = seat.step(a_u);
    stats.add_sample(a_u, out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    if (!std::isfinite(out.x_r_m) || !std::isfinite(out.v_r_m_per_s) ||
        !std::isfinite(out.a_x_m_per_s2) || !std::isfinite(out.friction_n))
      ++non_finite;
    whole.add(
        static_cast<long double>(a_u) * static_cast<long double>(a_u),
        static_cast<long double>(out.a_x_m_per_s2) * static_cast<long double>(out.a_x_m_per_s2),
        static_cast<long double>(out.stuck_fraction));
    if (n + 1 == next_checkpoint || n + 1 == o.samples) {
      next_checkpoint += every;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      report.row(whole_stream_checkpoint(n, stats, whole, seconds, tolerance, report), false);
    }
  }
  const bool counts = stats.samples() == o.samples && stats.steps() == o.samples - 1;
  std::printf(
      "soak oscillator %s: %" PRIu64 " samples (%.0f s of ride), non-finite outputs %" PRIu64
      ", rejected inputs %" PRIu64 ", state resets %" PRIu64 ", event budget hits %" PRIu64
      ", sample count %s, statistics vs blockwise %s (tolerance %.1e)\n",
      sizeof(T) == 4 ? "float" : "double", o.samples, static_cast<double>(o.samples) * p.dt_s,
      non_finite, seat.rejected_inputs(), seat.state_resets(), seat.event_budget_exhausted(),
      counts ? "exact" : "WRONG", report.failures() == 0 ? "agree" : "DIFFER", tolerance);
  return report.failures() == 0 && counts && non_finite == 0 && seat.state_resets() == 0 &&
                 seat.rejected_inputs() == 0 && seat.event_budget_exhausted() == 0
             ? 0
             : 1;
}

template int soak_oscillator<float>(const Options& o);
template int soak_oscillator<double>(const Options& o);

}  // namespace stickslip::soak
