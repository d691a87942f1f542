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
// --path oscillator: the earlier soak, the oscillator and RunningStatistics only (the same
// whole-stream checks, no observer).
// --fault: make one check fail on purpose, to show it can (CTest runs each on 1e6 samples):
//   nan    one per-sample output replaced by NaN before the finiteness check;
//   count  the observer is given one sample twice (a lost tick of the time keeping);
//   stats  one block of the window recomputation scaled by 1.01 (a statistics error of 1e-3).
// Prints K checkpoints (and writes them to FILE as CSV). Exit status 1 if any check fails,
// with "soak FAILED:" and the failed checks.
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/iso2631_weighting.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/oscillator.hpp"
#include "stickslip/observer/observer.hpp"
#include "stickslip/observer/regime_tracker.hpp"

namespace {

using namespace stickslip;

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kRecomputeBlock = 1000000;

enum class Fault { none, nan, count, stats };

struct Options {
  std::uint64_t samples = 1000000000ull;
  bool in_float = true;
  bool observer = true;
  int checkpoints = 10;
  const char* csv = nullptr;
  Fault fault = Fault::none;
};

double relative(double a, double b) {
  const double scale = std::fmax(std::fabs(a), std::fabs(b));
  return scale > 0.0 ? std::fabs(a - b) / scale : 0.0;
}

// The scene and its input, shared by both paths.
template <typename T>
struct Scene {
  std::vector<T> input;  // one loop of the recording
  OscillatorParams params;
};

template <typename T>
Scene<T> lorry_scene() {
  host::GeneratorSpec spec;
  spec.kind = host::SignalKind::lorry;
  spec.rms_m_per_s2 = 0.35;
  spec.duration_s = 600.0;
  spec.dt_s = 1e-3;
  spec.seed = 1;
  const std::vector<double> recording = host::generate_signal(spec);
  Scene<T> scene;
  scene.input.assign(recording.begin(), recording.end() - 1);  // a loop: last sample = first period
  OscillatorParams& p = scene.params;
  p.model = FrictionModel::stick_slip;
  p.integrator = Integrator::exact;
  p.dt_s = spec.dt_s;
  p.kinetic_friction_n = 0.8 * kPi * std::sqrt(2.0) * p.mass_kg * spec.rms_m_per_s2 / 4.0;
  p.static_friction_n = p.kinetic_friction_n;
  return scene;
}

// The whole-stream recomputation: squares and stuck fractions summed in long double, in blocks
// of 1e6 samples (a plain long double sum over 1e9 terms would itself lose ~1e-10).
struct WholeStreamReference {
  long double total_u = 0, total_x = 0, total_stuck = 0;
  long double block_u = 0, block_x = 0, block_stuck = 0;
  std::uint64_t in_block = 0;

  void add(long double u_sq, long double x_sq, long double stuck) {
    block_u += u_sq;
    block_x += x_sq;
    block_stuck += stuck;
    if (++in_block == kRecomputeBlock) {
      total_u += block_u;
      total_x += block_x;
      total_stuck += block_stuck;
      block_u = block_x = block_stuck = 0;
      in_block = 0;
    }
  }
  double rms_ratio() const {
    return static_cast<double>(std::sqrt((total_x + block_x) / (total_u + block_u)));
  }
  double stuck_share(std::uint64_t steps) const {
    return static_cast<double>((total_stuck + block_stuck) / static_cast<long double>(steps));
  }
};

// m <- m + g (v - m) in long double, with a running first-order bound of how far the same
// recurrence evaluated in T (unit roundoff u) can be from it: each step rounds v (a square),
// v - m, the product and the sum, and the recurrence forgets old errors at the rate 1 - g.
struct ExponentialReference {
  long double mean = 0;
  double bound = 0;      // on |m_T - m|, first order in u
  double max_mean = 0;   // for MTVV: the largest m so far ...
  double max_bound = 0;  // ... and the largest bound so far (|max m_T - max m| <= max bound)

  void add(long double value, long double gain, double u) {
    const double previous = static_cast<double>(mean);
    mean += gain * (value - mean);
    const double g = static_cast<double>(gain), v = std::fabs(static_cast<double>(value));
    bound = (1.0 - g) * bound + u * (std::fabs(static_cast<double>(mean)) + 3.0 * g * v +
                                     2.0 * g * std::fabs(previous));
    max_mean = std::fmax(max_mean, static_cast<double>(mean));
    max_bound = std::fmax(max_bound, bound);
  }
};

// One block of the window recomputation.
struct ReferenceBlock {
  long double u_sq = 0, x_sq = 0, stuck = 0;
  std::uint32_t samples = 0, stick_events = 0, slip_events = 0;
};

struct Checkpoint {
  std::uint64_t samples;
  double t_ax, t_ax_block, p, p_block, d_t, d_p, window_worst, exp_worst, comfort_worst, ns;
};

// Ratio of a difference to its tolerance: <= 1 passes.
double against(double difference, double tolerance) {
  return tolerance > 0.0 ? difference / tolerance : (difference == 0.0 ? 0.0 : HUGE_VAL);
}

class Report {
 public:
  explicit Report(const Options& o) : options_(o) {}
  bool open_csv(bool observer) {
    if (options_.csv == nullptr) return true;
    csv_ = std::fopen(options_.csv, "w");
    if (csv_ == nullptr) return false;
    std::fprintf(
        csv_,
        "samples,T_ax,T_ax_blockwise,p,p_blockwise,rel_diff_T_ax,rel_diff_p,%sns_per_sample\n",
        observer ? "window_worst_over_tol,exp_worst_over_tol,comfort_worst_over_tol," : "");
    return true;
  }
  void header(bool observer) const {
    std::printf("%14s %12s %12s %10s %10s %9s %9s", "samples", "T_ax", "T_ax_block", "p", "p_block",
                "dT_ax", "dp");
    if (observer) std::printf(" %9s %9s %9s", "win/tol", "exp/tol", "cmf/tol");
    std::printf(" %8s\n", "ns/smp");
  }
  void row(const Checkpoint& c, bool observer) const {
    std::printf("%14" PRIu64 " %12.9f %12.9f %10.7f %10.7f %9.2e %9.2e", c.samples, c.t_ax,
                c.t_ax_block, c.p, c.p_block, c.d_t, c.d_p);
    if (observer) std::printf(" %9.2e %9.2e %9.2e", c.window_worst, c.exp_worst, c.comfort_worst);
    std::printf(" %8.2f\n", c.ns);
    std::fflush(stdout);
    if (csv_ == nullptr) return;
    std::fprintf(csv_, "%" PRIu64 ",%.17g,%.17g,%.17g,%.17g,%.3e,%.3e,", c.samples, c.t_ax,
                 c.t_ax_block, c.p, c.p_block, c.d_t, c.d_p);
    if (observer)
      std::fprintf(csv_, "%.3e,%.3e,%.3e,", c.window_worst, c.exp_worst, c.comfort_worst);
    std::fprintf(csv_, "%.3f\n", c.ns);
  }
  ~Report() {
    if (csv_ != nullptr) std::fclose(csv_);
  }
  // A failed check: remembered (first occurrence printed) and counted.
  void fail(const char* what, std::uint64_t n, double value, double limit) {
    ++failures_;
    if (failures_ <= 5)
      std::printf("soak check failed at sample %" PRIu64 ": %s (%.6g vs %.6g)\n", n, what, value,
                  limit);
    if (first_.empty()) first_ = what;
  }
  std::uint64_t failures() const { return failures_; }
  const std::string& first() const { return first_; }

 private:
  const Options& options_;
  std::FILE* csv_ = nullptr;
  std::uint64_t failures_ = 0;
  std::string first_;
};

// The whole-stream checkpoint both paths take: the running statistics against the long-double
// recomputation after n + 1 samples, each beyond `tolerance` reported.
template <typename Statistics>
Checkpoint whole_stream_checkpoint(std::uint64_t n, const Statistics& stats,
                                   const WholeStreamReference& whole, double seconds,
                                   double tolerance, Report& report) {
  Checkpoint c{};
  c.samples = n + 1;
  c.t_ax = stats.transmissibility();
  c.t_ax_block = whole.rms_ratio();
  c.p = stats.stick_probability();
  c.p_block = whole.stuck_share(n);
  c.d_t = relative(c.t_ax, c.t_ax_block);
  c.d_p = relative(c.p, c.p_block);
  c.ns = seconds * 1e9 / static_cast<double>(n);
  if (!(c.d_t <= tolerance)) report.fail("whole-stream T_ax vs blockwise", n + 1, c.d_t, tolerance);
  if (!(c.d_p <= tolerance)) report.fail("whole-stream p vs blockwise", n + 1, c.d_p, tolerance);
  return c;
}

// --path oscillator: the oscillator and RunningStatistics only.
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
  whole.add(static_cast<long double>(input[0]) * input[0], static_cast<long double>(a_x0) * a_x0,
            0);
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
    whole.add(static_cast<long double>(a_u) * a_u,
              static_cast<long double>(out.a_x_m_per_s2) * out.a_x_m_per_s2, out.stuck_fraction);
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

// --path observer (the default).
template <typename T>
int soak_observer(const Options& o) {
  using Law = CoulombStickSlip;
  constexpr std::size_t kBlocks = 10;  // Observer's default, as the ECU node uses it
  const Scene<T> scene = lorry_scene<T>();
  const std::vector<T>& input = scene.input;
  const std::uint64_t period = input.size();
  const double dt = scene.params.dt_s;

  // As SeatModelFor (sim_host/src/bus/ecu_node.cpp) configures it.
  ObserverParams op;
  op.model = scene.params;
  op.window_s = std::fmax(10.0, 10.0 * dt);
  op.exponential_time_s = std::fmax(10.0, dt);
  Observer<T, Law, kBlocks> observer;
  const ConfigResult configured = observer.configure(op);
  if (!configured.ok()) {
    std::fprintf(stderr, "soak: %s\n", configured.message.c_str());
    return 1;
  }
  // The recomputation's own weighting filters and gains, configured as RideComfort and the
  // exponential window configure theirs.
  WeightingFilter<T> floor_filter, seat_filter;
  floor_filter.configure(op.weighting, 1.0 / dt);
  seat_filter.configure(op.weighting, 1.0 / dt);
  const long double exp_gain = static_cast<T>(-std::expm1(-dt / op.exponential_time_s));
  const double comfort_dt = 1.0 / (1.0 / dt);  // RideComfort keeps 1 / its sample rate
  const long double running_gain = static_cast<T>(-std::expm1(-comfort_dt / 1.0));
  const std::uint32_t per_block =
      static_cast<std::uint32_t>(std::round(op.window_s / (dt * double(kBlocks))));

  Report report(o);
  if (!report.open_csv(true)) {
    std::fprintf(stderr, "soak: cannot write %s\n", o.csv);
    return 2;
  }
  std::printf(
      "through the observer: window %u blocks of %u samples, exponential tau %.3g s, %s comfort\n",
      unsigned(kBlocks), per_block, op.exponential_time_s,
      op.weighting == ComfortWeighting::wk ? "Wk" : "Wd");
  report.header(true);

  const double eps = static_cast<double>(std::numeric_limits<T>::epsilon());
  const double u = eps / 2.0;
  const double whole_tolerance = 256.0 * eps;  // RunningStatistics / RideComfort: 256-sample blocks
  const double window_tolerance = double(per_block + kBlocks) * eps;
  double window_worst = 0.0, exp_worst = 0.0, comfort_worst = 0.0;  // |difference| / tolerance
  double whole_worst = 0.0;

  // The reset sample: the observer's model state, statistics and comfort.
  RunningStatistics<T> stats;  // the ECU node's whole-stream statistics beside the observer
  stats.reset();
  observer.reset(input[0]);
  StepOutput<T> out = observer.estimate().model;
  stats.add_sample(input[0], out.a_x_m_per_s2);
  WholeStreamReference whole;
  whole.add(static_cast<long double>(input[0]) * input[0],
            static_cast<long double>(out.a_x_m_per_s2) * out.a_x_m_per_s2, 0);
  // Comfort recomputation: weighted squares and fourth powers, blockwise in long double.
  WholeStreamReference floor_sq, seat_sq;  // (only the u channel of each is used for squares)
  WholeStreamReference fourth;             // u channel: floor^4, x channel: seat^4
  ExponentialReference running_ms;         // the seat's 1 s running mean square (MTVV)
  T seat_peak = T(0);
  const auto comfort_sample = [&](T a_floor, T a_seat) {
    const long double f = floor_filter.step(a_floor), s = seat_filter.step(a_seat);
    const T s_t = static_cast<T>(s);
    seat_peak = std::fabs(s_t) > seat_peak ? std::fabs(s_t) : seat_peak;
    floor_sq.add(f * f, 0, 0);
    seat_sq.add(s * s, 0, 0);
    fourth.add(f * f * f * f, s * s * s * s, 0);
    running_ms.add(s * s, running_gain, u);
  };
  comfort_sample(input[0], out.a_x_m_per_s2);

  ReferenceBlock blocks[kBlocks], current;
  std::size_t next_block = 0;
  std::uint64_t blocks_done = 0;
  ExponentialReference exp_u, exp_x, exp_stuck;
  RegimeTracker regime;
  regime.configure(op.regime_hysteresis_k);
  bool was_stuck = out.stuck;

  std::uint64_t non_finite = 0, block_checks = 0;
  const std::uint64_t every = o.samples / static_cast<std::uint64_t>(o.checkpoints);
  std::uint64_t next_checkpoint = every;
  std::uint64_t index = 0;  // into the looped recording
  const auto start = std::chrono::steady_clock::now();
  const auto finite = [](double v) { return std::isfinite(v); };
  // For the record only (never used for time): what accumulated clocks would read at the end.
  float t_float_sum = 0.0f;
  double t_double_sum = 0.0;
  const float dt_float = static_cast<float>(dt);
  for (std::uint64_t n = 1; n < o.samples; ++n) {  // time t = n dt: an integer, never accumulated
    if (++index == period) index = 0;
    const T a_u = input[index];
    t_float_sum += dt_float;
    t_double_sum += dt;
    if (o.fault == Fault::count && n == o.samples / 2) observer.update(a_u);  // one tick too many
    const ObserverEstimate<T>& e = observer.update(a_u);
    out = e.model;
    stats.add_sample(a_u, out.a_x_m_per_s2);
    stats.add_step(out.stuck_fraction);
    T checked_x_r = out.x_r_m;
    if (o.fault == Fault::nan && n == o.samples / 2)
      checked_x_r = std::numeric_limits<T>::quiet_NaN();
    if (!std::isfinite(checked_x_r) || !std::isfinite(out.v_r_m_per_s) ||
        !std::isfinite(out.a_x_m_per_s2) || !std::isfinite(out.friction_n) ||
        !std::isfinite(out.stuck_time_s) || !std::isfinite(out.stuck_fraction) ||
        !std::isfinite(e.residual_m_per_s2) || !std::isfinite(e.measured_friction_n)) {
      if (non_finite++ == 0) report.fail("non-finite per-sample observer output", n, 0, 0);
    }

    const long double u_sq = static_cast<long double>(a_u) * a_u;
    const long double x_sq = static_cast<long double>(out.a_x_m_per_s2) * out.a_x_m_per_s2;
    const long double stuck = out.stuck_fraction;
    whole.add(u_sq, x_sq, stuck);
    comfort_sample(a_u, out.a_x_m_per_s2);
    exp_u.add(u_sq, exp_gain, u);
    exp_x.add(x_sq, exp_gain, u);
    exp_stuck.add(stuck, exp_gain, u);
    current.u_sq += u_sq;
    current.x_sq += x_sq;
    current.stuck += stuck;
    current.stick_events += (out.stuck && !was_stuck) ? 1u : 0u;
    current.slip_events += (!out.stuck && was_stuck) ? 1u : 0u;
    was_stuck = out.stuck;
    ++current.samples;

    if (n % per_block == 0) {  // the integer count says a window block completed here
      if (o.fault == Fault::stats && blocks_done == 3) current.u_sq *= 1.01L;
      blocks[next_block] = current;
      next_block = next_block + 1 == kBlocks ? 0 : next_block + 1;
      ++blocks_done;
      current = ReferenceBlock{};
      ReferenceBlock w;
      for (const ReferenceBlock& b : blocks) {
        w.u_sq += b.u_sq;
        w.x_sq += b.x_sq;
        w.stuck += b.stuck;
        w.samples += b.samples;
        w.stick_events += b.stick_events;
        w.slip_events += b.slip_events;
      }
      const ObserverSummary s = observer.summary();
      ++block_checks;
      // Time keeping: this block ended exactly here, and the window covers exactly its samples.
      const std::uint32_t expected =
          static_cast<std::uint32_t>(std::min<std::uint64_t>(blocks_done, kBlocks)) * per_block;
      if (w.samples != expected || s.window_s != double(expected) * dt || observer.samples() != n ||
          s.window_full != (blocks_done >= kBlocks))
        report.fail("window block boundary / sample count", n, s.window_s, double(expected) * dt);
      // Finiteness of every published figure.
      const RideComfort<T>& comfort = observer.comfort();
      const double figures[] = {s.rms_u_m_per_s2,
                                s.rms_x_m_per_s2,
                                s.transmissibility,
                                s.stick_probability,
                                s.den_hartog_k,
                                s.window_s,
                                s.exp_rms_u_m_per_s2,
                                s.exp_rms_x_m_per_s2,
                                s.exp_transmissibility,
                                s.exp_stick_probability,
                                s.exp_den_hartog_k,
                                s.residual_rms_m_per_s2,
                                comfort.floor_weighted_rms(),
                                comfort.seat_weighted_rms(),
                                comfort.seat_ratio(),
                                comfort.seat_vdv(),
                                comfort.floor_vdv(),
                                comfort.seat_running_rms(),
                                comfort.seat_mtvv(),
                                comfort.seat_peak(),
                                comfort.seat_crest_factor()};
      if (!std::all_of(std::begin(figures), std::end(figures), finite))
        report.fail("non-finite observer figure", n, 0, 0);
      // Window statistics against the blockwise recomputation.
      const long double count = w.samples;
      const double rms_u = static_cast<double>(std::sqrt(w.u_sq / count));
      const double rms_x = static_cast<double>(std::sqrt(w.x_sq / count));
      const double p_window = static_cast<double>(w.stuck / count);
      const double window_d[] = {
          relative(s.rms_u_m_per_s2, rms_u), relative(s.rms_x_m_per_s2, rms_x),
          relative(s.transmissibility, rms_x / rms_u), relative(s.stick_probability, p_window)};
      for (double d : window_d) {
        window_worst = std::fmax(window_worst, against(d, window_tolerance));
        if (!(d <= window_tolerance))
          report.fail("window statistics vs blockwise", n, d, window_tolerance);
      }
      if (s.stick_events != w.stick_events || s.slip_events != w.slip_events)
        report.fail("window stick/slip events vs recount", n, s.stick_events, w.stick_events);
      if (blocks_done >= kBlocks)
        regime.update(den_hartog_factor(op.model.kinetic_friction_n, op.model.mass_kg, rms_u));
      if (s.regime != regime.regime() || s.regime_known != regime.known() ||
          s.regime_changes != regime.changes())
        report.fail("regime vs a tracker fed the recomputed K", n, s.regime_changes,
                    regime.changes());
      // Exponential window and running RMS: mean squares against the long-double recurrence.
      // (The observed figure is a root read back and squared in double: a few ulp of double.)
      const auto check_recurrence = [&](const char* what, double& worst, double observed_mean,
                                        double mean, double bound) {
        const double tolerance = 2.0 * bound + 8.0 * DBL_EPSILON * std::fabs(mean);
        const double ratio = against(std::fabs(observed_mean - mean), tolerance);
        worst = std::fmax(worst, ratio);
        if (!(ratio <= 1.0)) report.fail(what, n, observed_mean, mean);
      };
      check_recurrence("exponential mean square a_u", exp_worst,
                       s.exp_rms_u_m_per_s2 * s.exp_rms_u_m_per_s2, static_cast<double>(exp_u.mean),
                       exp_u.bound);
      check_recurrence("exponential mean square a_x", exp_worst,
                       s.exp_rms_x_m_per_s2 * s.exp_rms_x_m_per_s2, static_cast<double>(exp_x.mean),
                       exp_x.bound);
      check_recurrence("exponential stuck share", exp_worst, s.exp_stick_probability,
                       static_cast<double>(exp_stuck.mean), exp_stuck.bound);
      check_recurrence("comfort running mean square", comfort_worst,
                       comfort.seat_running_rms() * comfort.seat_running_rms(),
                       static_cast<double>(running_ms.mean), running_ms.bound);
      check_recurrence("comfort MTVV^2", comfort_worst, comfort.seat_mtvv() * comfort.seat_mtvv(),
                       running_ms.max_mean, running_ms.max_bound);
      // Ride comfort against the blockwise recomputation of the same weighted samples.
      const long double total = static_cast<long double>(n + 1);  // the reset sample too
      const double comfort_d[] = {
          relative(comfort.floor_weighted_rms(),
                   static_cast<double>(std::sqrt((floor_sq.total_u + floor_sq.block_u) / total))),
          relative(comfort.seat_weighted_rms(),
                   static_cast<double>(std::sqrt((seat_sq.total_u + seat_sq.block_u) / total))),
          relative(comfort.floor_vdv(), static_cast<double>(std::sqrt(std::sqrt(
                                            (fourth.total_u + fourth.block_u) * comfort_dt)))),
          relative(comfort.seat_vdv(), static_cast<double>(std::sqrt(std::sqrt(
                                           (fourth.total_x + fourth.block_x) * comfort_dt))))};
      for (double d : comfort_d) {
        comfort_worst = std::fmax(comfort_worst, against(d, whole_tolerance));
        if (!(d <= whole_tolerance))
          report.fail("ride comfort vs blockwise", n, d, whole_tolerance);
      }
      if (comfort.seat_peak() != static_cast<double>(seat_peak))
        report.fail("comfort peak vs the recomputation's (same weighted samples)", n,
                    comfort.seat_peak(), static_cast<double>(seat_peak));
    }

    if (n + 1 == next_checkpoint || n + 1 == o.samples) {
      next_checkpoint += every;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      Checkpoint c = whole_stream_checkpoint(n, stats, whole, seconds, whole_tolerance, report);
      c.window_worst = window_worst;
      c.exp_worst = exp_worst;
      c.comfort_worst = comfort_worst;
      report.row(c, true);
      whole_worst = std::fmax(whole_worst, std::fmax(c.d_t, c.d_p) / whole_tolerance);
    }
  }

  // Time keeping at the end: every count is the integer sample count; t = n dt from it.
  const std::uint64_t updates = o.samples - 1;
  const bool counts = observer.samples() == updates && observer.comfort().samples() == o.samples &&
                      stats.samples() == o.samples && stats.steps() == updates;
  if (!counts)
    report.fail("sample counts (observer, comfort, statistics) vs the integer count", updates,
                static_cast<double>(observer.samples()), static_cast<double>(updates));
  // t = n dt is one rounding of the exact product, however long the run: within half an ulp.
  const double t_end = static_cast<double>(updates) * dt;
  const long double t_exact = static_cast<long double>(updates) * static_cast<long double>(dt);
  const double t_error = static_cast<double>(std::fabs(static_cast<long double>(t_end) - t_exact));
  if (!(t_error <= 0.5 * std::ldexp(1.0, std::ilogb(t_end) - 52)))
    report.fail("t = n dt is off the long-double product by more than half an ulp", updates, t_end,
                static_cast<double>(t_exact));
  const Oscillator<T, Law>& seat = observer.model();
  if (seat.rejected_inputs() != 0 || seat.state_resets() != 0 || seat.event_budget_exhausted() != 0)
    report.fail(
        "rejected inputs / state resets / event budget hits", updates,
        double(seat.rejected_inputs() + seat.state_resets() + seat.event_budget_exhausted()), 0);
  if (block_checks != updates / per_block)
    report.fail("block checks", updates, double(block_checks), 0);

  const ObserverSummary s = observer.summary();
  std::printf(
      "soak observer %s: %" PRIu64
      " samples (t = n dt = %.3f s of ride, %.1e s from the "
      "exact product; accumulated t += dt would read %.3f s in double, %.3f s in float), "
      "non-finite outputs %" PRIu64 ", rejected inputs %" PRIu64 ", state resets %" PRIu64
      ", event budget hits %" PRIu64 ", sample counts %s, %" PRIu64 " window blocks checked\n",
      sizeof(T) == 4 ? "float" : "double", o.samples, t_end, t_error, t_double_sum,
      static_cast<double>(t_float_sum), non_finite, seat.rejected_inputs(), seat.state_resets(),
      seat.event_budget_exhausted(), counts ? "exact" : "WRONG", block_checks);
  std::printf(
      "  last window: T_ax %.9f p %.7f K %.4f regime %s (%u changes); exponential T_ax %.9f; "
      "comfort: seat Wk RMS %.6f m/s^2, SEAT %.6f, VDV %.4f m/s^1.75, MTVV %.6f m/s^2\n",
      s.transmissibility, s.stick_probability, s.den_hartog_k, regime_name(s.regime),
      s.regime_changes, s.exp_transmissibility, observer.comfort().seat_weighted_rms(),
      observer.comfort().seat_ratio(), observer.comfort().seat_vdv(),
      observer.comfort().seat_mtvv());
  std::printf(
      "  worst difference / tolerance: window %.2e (tolerance %.2e relative), exponential and "
      "running RMS %.2e (of twice the running bound), comfort %.2e and whole stream %.2e "
      "(tolerance %.2e relative)\n",
      window_worst, window_tolerance, exp_worst, comfort_worst, whole_worst, whole_tolerance);
  if (report.failures() > 0) {
    std::printf("soak FAILED: %" PRIu64 " failed checks, the first: %s\n", report.failures(),
                report.first().c_str());
    return 1;
  }
  std::printf("soak passed\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool usage = false;
  for (int i = 1; i < argc && !usage; ++i) {
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
    ++i;
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
