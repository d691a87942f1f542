// stickslip_soak [--samples N] [--type float|double] [--checkpoints K] [--csv FILE]
//
// The long run: N samples (default 1e9) of the lorry-like scene (K = 0.8, b = 504 N s/m,
// F_fs = F_fk; the 600 s lorry recording at 1 ms, seed 1, RMS 0.35 m/s^2, played in a loop) through
// the Coulomb stick-slip oscillator and RunningStatistics, as the ECU runs it. Checks:
//   - no output is NaN/Inf; no rejected input, state reset or event-budget hit;
//   - time is the integer sample count (uint64); the statistics' step count equals it exactly;
//   - the statistics equal a blockwise recomputation (blocks of 1e6 samples summed in long
//     double from the same outputs) within the statistics' documented error: 256 ulp of the
//     scalar type relative (RunningStatistics sums blocks of 256 samples plainly, then
//     compensated).
// Prints K checkpoints (and writes them to FILE as CSV): samples, T_ax and p running and
// recomputed, their relative differences, ns per sample. Exit status 1 if any check fails.
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "stickslip/host/signal_generator.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"

namespace {

using namespace stickslip;

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kRecomputeBlock = 1000000;

struct Options {
  std::uint64_t samples = 1000000000ull;
  bool in_float = true;
  int checkpoints = 10;
  const char* csv = nullptr;
};

double relative(double a, double b) {
  const double scale = std::fmax(std::fabs(a), std::fabs(b));
  return scale > 0.0 ? std::fabs(a - b) / scale : 0.0;
}

template <typename T>
int soak(const Options& o) {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::lorry;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = 600.0;
  spec.dt_s = 1e-3;
  spec.seed = 1;
  const std::vector<double> recording = host::generate_signal(spec);
  std::vector<T> input(recording.begin(), recording.end() - 1);  // a loop: last sample = first period
  const std::uint64_t period = input.size();

  OscillatorParams p;
  p.model = FrictionModel::stick_slip;
  p.integrator = Integrator::exact;
  p.dt_s = spec.dt_s;
  p.kinetic_friction_n = 0.8 * kPi * std::sqrt(2.0) * p.mass_kg * spec.rms_m_per_s2 / 4.0;
  p.static_friction_n = p.kinetic_friction_n;
  Oscillator<T, CoulombStickSlip> seat;
  const auto config = seat.configure(p);
  if (!config.ok()) {
    std::fprintf(stderr, "soak: %s\n", config.message.c_str());
    return 1;
  }

  std::FILE* csv = o.csv != nullptr ? std::fopen(o.csv, "w") : nullptr;
  if (o.csv != nullptr && csv == nullptr) {
    std::fprintf(stderr, "soak: cannot write %s\n", o.csv);
    return 2;
  }
  if (csv != nullptr)
    std::fprintf(csv, "samples,T_ax,T_ax_blockwise,p,p_blockwise,rel_diff_T_ax,rel_diff_p,ns_per_sample\n");
  std::printf("%14s %12s %12s %10s %10s %10s %10s %8s\n", "samples", "T_ax", "T_ax_block", "p",
              "p_block", "dT_ax", "dp", "ns/smp");

  // The statistics' error bound: 256 ulp of T, relative, plus the recomputation's own (long
  // double) which is far below it.
  const double tolerance = 256.0 * static_cast<double>(std::numeric_limits<T>::epsilon());
  RunningStatistics<T> stats;
  stats.reset();
  seat.reset(T(0), T(0), input[0]);
  const T a_x0 = seat.current().a_x_m_per_s2;
  stats.add_sample(input[0], a_x0);
  long double total_u = 0, total_x = 0, total_stuck = 0;  // the blockwise recomputation
  long double block_u = static_cast<long double>(input[0]) * static_cast<long double>(input[0]);
  long double block_x = static_cast<long double>(a_x0) * static_cast<long double>(a_x0);
  long double block_stuck = 0;
  std::uint64_t non_finite = 0;
  bool ok = true;
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
    block_u += static_cast<long double>(a_u) * static_cast<long double>(a_u);
    block_x += static_cast<long double>(out.a_x_m_per_s2) * static_cast<long double>(out.a_x_m_per_s2);
    block_stuck += static_cast<long double>(out.stuck_fraction);
    if ((n + 1) % kRecomputeBlock == 0) {
      total_u += block_u;
      total_x += block_x;
      total_stuck += block_stuck;
      block_u = block_x = block_stuck = 0;
    }
    if (n + 1 == next_checkpoint || n + 1 == o.samples) {
      next_checkpoint += every;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const long double count = static_cast<long double>(n + 1);
      const double rms_u = static_cast<double>(std::sqrt((total_u + block_u) / count));
      const double rms_x = static_cast<double>(std::sqrt((total_x + block_x) / count));
      const double t_block = rms_x / rms_u;
      const double p_block = static_cast<double>((total_stuck + block_stuck) / static_cast<long double>(n));
      const double d_t = relative(stats.transmissibility(), t_block);
      const double d_p = relative(stats.stick_probability(), p_block);
      const double ns = seconds * 1e9 / static_cast<double>(n);
      std::printf("%14" PRIu64 " %12.9f %12.9f %10.7f %10.7f %10.2e %10.2e %8.2f\n", n + 1,
                  stats.transmissibility(), t_block, stats.stick_probability(), p_block, d_t, d_p, ns);
      std::fflush(stdout);
      if (csv != nullptr)
        std::fprintf(csv, "%" PRIu64 ",%.17g,%.17g,%.17g,%.17g,%.3e,%.3e,%.3f\n", n + 1,
                     stats.transmissibility(), t_block, stats.stick_probability(), p_block, d_t, d_p, ns);
      if (!(d_t <= tolerance) || !(d_p <= tolerance)) ok = false;
    }
  }
  if (csv != nullptr) std::fclose(csv);
  const bool counts = stats.samples() == o.samples && stats.steps() == o.samples - 1;
  std::printf("soak %s: %" PRIu64 " samples (%.0f s of ride), non-finite outputs %" PRIu64
              ", rejected inputs %" PRIu64 ", state resets %" PRIu64 ", event budget hits %" PRIu64
              ", sample count %s, statistics vs blockwise %s (tolerance %.1e)\n",
              sizeof(T) == 4 ? "float" : "double", o.samples, static_cast<double>(o.samples) * p.dt_s,
              non_finite, seat.rejected_inputs(), seat.state_resets(), seat.event_budget_exhausted(),
              counts ? "exact" : "WRONG", ok ? "agree" : "DIFFER", tolerance);
  return ok && counts && non_finite == 0 && seat.state_resets() == 0 &&
                 seat.rejected_inputs() == 0 && seat.event_budget_exhausted() == 0
             ? 0
             : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (std::strcmp(argv[i], "--samples") == 0 && has_value) {
      o.samples = static_cast<std::uint64_t>(std::strtod(argv[++i], nullptr));
    } else if (std::strcmp(argv[i], "--type") == 0 && has_value) {
      const std::string type = argv[++i];
      if (type != "float" && type != "double") o.samples = 0;
      o.in_float = type == "float";
    } else if (std::strcmp(argv[i], "--checkpoints") == 0 && has_value) {
      o.checkpoints = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--csv") == 0 && has_value) {
      o.csv = argv[++i];
    } else {
      o.samples = 0;
      break;
    }
  }
  if (o.samples < 1000 || o.checkpoints < 1 || static_cast<std::uint64_t>(o.checkpoints) > o.samples) {
    std::fprintf(stderr, "usage: %s [--samples N>=1000] [--type float|double] [--checkpoints K] [--csv FILE]\n",
                 argv[0]);
    return 2;
  }
  return o.in_float ? soak<float>(o) : soak<double>(o);
}
