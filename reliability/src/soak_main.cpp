// stickslip_soak [--samples N] [--type float|double] [--path observer|oscillator]
//                [--checkpoints K] [--csv FILE] [--fault none|nan|count|stats]
//
// The long run: N samples (default 1e9) of the lorry-like scene (K = 0.8, b = 504 N s/m,
// F_fs = F_fk; the 600 s lorry recording at 1 ms, seed 1, RMS 0.35 m/s^2, played in a loop).
//
// --path observer (the default): through the Observer as the ECU node drives it
// (sim_host/src/bus/ecu_node.cpp: Observer<T, law> with a 10 s window of 10 blocks, a 10 s
// exponential window and Wk ride comfort, update(a_u) per sample after reset(a_u0), and the
// whole-stream RunningStatistics beside it). Checks:
//   - no NaN/Inf in any observer output: every field of every per-sample estimate; the window,
//     exponential, regime and ride-comfort figures at every completed window block;
//   - time keeping: time is an integer sample count (uint64), t = n dt. The observer's update
//     count, the comfort's and the statistics' sample counts equal it exactly, every block of the
//     window completes exactly where the count says (its window_s is exactly the integer
//     count times dt), and at the end n dt equals the long-double product (no drift);
//   - the observer's statistics equal a recomputation from the same samples in long double:
//       window (blockwise, mirroring the 10 blocks): RMS a_u, RMS a_x, T_ax, p within
//         (samples per block + blocks) ulp of T: the window sums per_block samples plainly in T,
//         then adds the blocks plainly: for positive terms the relative error is at most
//         (per_block + blocks - 1) u + u for the square (u = ulp/2), and T_ax adds the halves
//         of both RMS errors, so one ulp per term is a margin of about 2 over the worst case;
//         stick and slip events exactly; the regime as a RegimeTracker fed with the recomputed K;
//       exponential window (the same recurrence in long double with the same gain): within twice
//         a running first-order bound of the float recurrence's rounding, E <- (1-g) E +
//         u (|m| + 3 g |v| + 2 g |m_prev|) (each step's roundings, forgotten at the rate 1-g);
//       ride comfort (blockwise, the weighted samples from a second weighting filter on the same
//         input, identical by construction: the peak must match to the bit): weighted RMS of
//         floor and seat and their VDV within 256 ulp (RideComfort's documented error, as
//         RunningStatistics'), the running RMS and MTVV within the recurrence bound above;
//       whole stream (RunningStatistics, blocks of 1e6 in long double): T_ax, p within 256 ulp.
//   - no rejected input, state reset or event-budget hit.
// --path oscillator: the oscillator and RunningStatistics only (the same whole-stream checks, no
// observer).
// --fault: make one check fail on purpose, to show it can (CTest runs each on 1e6 samples):
//   nan    one per-sample output replaced by NaN before the finiteness check;
//   count  the observer is given one sample twice (a lost tick of the time keeping);
//   stats  one block of the window recomputation scaled by 1.01 (a statistics error of 1e-3).
// Prints K checkpoints (and writes them to FILE as CSV). Exit status 1 if any check fails,
// with "soak FAILED:" and the failed checks.
//
// The pieces: soak/oracle.hpp (the long-double recomputation), soak/observer_run.cpp and
// soak/oscillator_run.cpp (the two paths), soak/report.* (checkpoint rows, failed checks).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "soak/options.hpp"
#include "soak/runner.hpp"

using namespace stickslip::soak;

int main(int argc, char** argv) {
  Options o;
  bool usage = false;
  for (int i = 1; i < argc && !usage; i += 2) {  // --option value pairs
    const bool has_value = i + 1 < argc;
    const std::string option = argv[i];
    const std::string value = has_value ? argv[i + 1] : "";
    if (!has_value) {
      usage = true;
    } else if (option == "--samples") {
      o.samples = static_cast<std::uint64_t>(std::strtod(value.c_str(), nullptr));
    } else if (option == "--type") {
      usage = value != "float" && value != "double";
      o.in_float = value == "float";
    } else if (option == "--path") {
      usage = value != "observer" && value != "oscillator";
      o.observer = value == "observer";
    } else if (option == "--checkpoints") {
      o.checkpoints = std::atoi(value.c_str());
    } else if (option == "--csv") {
      o.csv = argv[i + 1];
    } else if (option == "--fault") {
      if (value == "none")
        o.fault = Fault::none;
      else if (value == "nan")
        o.fault = Fault::nan;
      else if (value == "count")
        o.fault = Fault::count;
      else if (value == "stats")
        o.fault = Fault::stats;
      else
        usage = true;
    } else {
      usage = true;
    }
  }
  if (usage || o.samples < 100000 || o.checkpoints < 1 ||
      static_cast<std::uint64_t>(o.checkpoints) > o.samples ||
      (!o.observer && o.fault != Fault::none)) {
    std::fprintf(stderr,
                 "usage: %s [--samples N>=1e5] [--type float|double] [--path observer|oscillator] "
                 "[--checkpoints K] [--csv FILE] [--fault none|nan|count|stats (observer path)]\n",
                 argv[0]);
    return 2;
  }
  if (!o.observer) return o.in_float ? soak_oscillator<float>(o) : soak_oscillator<double>(o);
  return o.in_float ? soak_observer<float>(o) : soak_observer<double>(o);
}
