// --path observer: the lorry scene through the Observer as the ECU node drives it, every output
// checked for finiteness, the time keeping against the integer sample count, and every statistic
// against the long-double oracle (see soak_main.cpp for the checks and their tolerances).
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <vector>

#include "soak/oracle.hpp"
#include "soak/report.hpp"
#include "soak/runner.hpp"
#include "soak/scene.hpp"
#include "stickslip/metrics/den_hartog.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/observer/observer.hpp"
#include "stickslip/observer/regime_tracker.hpp"

namespace stickslip::soak {
namespace {

template <typename T>
class ObserverRun {
 public:
  using Law = CoulombStickSlip;
  static constexpr std::size_t kBlocks = 10;  // Observer's default, as the ECU node uses it

  explicit ObserverRun(const Options& o)
      : o_(o), scene_(lorry_scene<T>()), dt_(scene_.params.dt_s), report_(o) {}
  int run();

 private:
  bool configure();
  void reset();
  void sample(std::uint64_t n, T a_u);
  void check_block(std::uint64_t n);
  void check_window(std::uint64_t n, const ReferenceBlock& w, const ObserverSummary& s);
  void check_recurrences(std::uint64_t n, const ObserverSummary& s);
  void check_comfort(std::uint64_t n);
  void checkpoint(std::uint64_t n);
  void check_end();
  void print_summary() const;

  const Options& o_;
  const Scene<T> scene_;
  const double dt_;
  ObserverParams op_;
  Observer<T, Law, kBlocks> observer_;
  Report report_;
  std::uint32_t per_block_ = 0;
  long double exp_gain_ = 0;
  double u_ = 0, whole_tolerance_ = 0, window_tolerance_ = 0;
  double window_worst_ = 0.0, exp_worst_ = 0.0, comfort_worst_ = 0.0;  // |difference| / tolerance
  double whole_worst_ = 0.0;

  RunningStatistics<T> stats_;  // the ECU node's whole-stream statistics beside the observer
  StepOutput<T> out_{};
  WholeStreamReference whole_;
  ComfortReference<T> comfort_;
  WindowReference<kBlocks> window_;
  ExponentialReference exp_u_, exp_x_, exp_stuck_;
  RegimeTracker regime_;
  bool was_stuck_ = false;

  std::uint64_t non_finite_ = 0, block_checks_ = 0;
  std::chrono::steady_clock::time_point start_;
  // For the record only (never used for time): what accumulated clocks would read at the end.
  float t_float_sum_ = 0.0f;
  double t_double_sum_ = 0.0;
  double t_end_ = 0.0, t_error_ = 0.0;
  bool counts_ = false;
};

// As SeatModelFor (sim_host/src/bus/ecu_node.cpp) configures it; the oracle's own weighting
// filters and gains configured as RideComfort and the exponential window configure theirs.
template <typename T>
bool ObserverRun<T>::configure() {
  op_.model = scene_.params;
  op_.window_s = std::fmax(10.0, 10.0 * dt_);
  op_.exponential_time_s = std::fmax(10.0, dt_);
  const ConfigResult configured = observer_.configure(op_);
  if (!configured.ok()) {
    std::fprintf(stderr, "soak: %s\n", configured.message.c_str());
    return false;
  }
  const double eps = static_cast<double>(std::numeric_limits<T>::epsilon());
  u_ = eps / 2.0;
  comfort_.configure(op_.weighting, dt_, u_);
  // The gain as the observer rounds it, held in long double.
  exp_gain_ = static_cast<long double>(static_cast<T>(-std::expm1(-dt_ / op_.exponential_time_s)));
  per_block_ = static_cast<std::uint32_t>(std::round(op_.window_s / (dt_ * double(kBlocks))));
  whole_tolerance_ = 256.0 * eps;  // RunningStatistics / RideComfort: 256-sample blocks
  window_tolerance_ = double(per_block_ + kBlocks) * eps;
  regime_.configure(op_.regime_hysteresis_k);
  return true;
}

// The reset sample: the observer's model state, statistics and comfort.
template <typename T>
void ObserverRun<T>::reset() {
  const std::vector<T>& input = scene_.input;
  stats_.reset();
  observer_.reset(input[0]);
  out_ = observer_.estimate().model;
  stats_.add_sample(input[0], out_.a_x_m_per_s2);
  whole_.add(
      static_cast<long double>(input[0]) * static_cast<long double>(input[0]),
      static_cast<long double>(out_.a_x_m_per_s2) * static_cast<long double>(out_.a_x_m_per_s2), 0);
  comfort_.add(input[0], out_.a_x_m_per_s2);
  was_stuck_ = out_.stuck;
}

// One sample through the observer, its outputs checked for finiteness and fed to the oracle.
template <typename T>
void ObserverRun<T>::sample(std::uint64_t n, T a_u) {
  t_float_sum_ += static_cast<float>(dt_);
  t_double_sum_ += dt_;
  if (o_.fault == Fault::count && n == o_.samples / 2) observer_.update(a_u);  // one tick too many
  const ObserverEstimate<T>& e = observer_.update(a_u);
  out_ = e.model;
  stats_.add_sample(a_u, out_.a_x_m_per_s2);
  stats_.add_step(out_.stuck_fraction);
  T checked_x_r = out_.x_r_m;
  if (o_.fault == Fault::nan && n == o_.samples / 2)
    checked_x_r = std::numeric_limits<T>::quiet_NaN();
  if (!std::isfinite(checked_x_r) || !std::isfinite(out_.v_r_m_per_s) ||
      !std::isfinite(out_.a_x_m_per_s2) || !std::isfinite(out_.friction_n) ||
      !std::isfinite(out_.stuck_time_s) || !std::isfinite(out_.stuck_fraction) ||
      !std::isfinite(e.residual_m_per_s2) || !std::isfinite(e.measured_friction_n)) {
    if (non_finite_++ == 0) report_.fail("non-finite per-sample observer output", n, 0, 0);
  }

  const long double u_sq = static_cast<long double>(a_u) * static_cast<long double>(a_u);
  const long double x_sq =
      static_cast<long double>(out_.a_x_m_per_s2) * static_cast<long double>(out_.a_x_m_per_s2);
  const long double stuck = static_cast<long double>(out_.stuck_fraction);
  whole_.add(u_sq, x_sq, stuck);
  comfort_.add(a_u, out_.a_x_m_per_s2);
  exp_u_.add(u_sq, exp_gain_, u_);
  exp_x_.add(x_sq, exp_gain_, u_);
  exp_stuck_.add(stuck, exp_gain_, u_);
  window_.add(u_sq, x_sq, stuck, out_.stuck && !was_stuck_, !out_.stuck && was_stuck_);
  was_stuck_ = out_.stuck;
}

// A window block completed at sample n: time keeping, finiteness of every published figure, and
// every statistic against the oracle.
template <typename T>
void ObserverRun<T>::check_block(std::uint64_t n) {
  if (o_.fault == Fault::stats && window_.blocks_done == 3) window_.current.u_sq *= 1.01L;
  const ReferenceBlock w = window_.complete_block();
  const ObserverSummary s = observer_.summary();
  ++block_checks_;
  // Time keeping: this block ended exactly here, and the window covers exactly its samples.
  const std::uint32_t expected =
      static_cast<std::uint32_t>(std::min<std::uint64_t>(window_.blocks_done, kBlocks)) *
      per_block_;
  if (w.samples != expected || s.window_s != double(expected) * dt_ || observer_.samples() != n ||
      s.window_full != (window_.blocks_done >= kBlocks))
    report_.fail("window block boundary / sample count", n, s.window_s, double(expected) * dt_);
  // Finiteness of every published figure.
  const RideComfort<T>& comfort = observer_.comfort();
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
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!std::all_of(std::begin(figures), std::end(figures), finite))
    report_.fail("non-finite observer figure", n, 0, 0);
  check_window(n, w, s);
  check_recurrences(n, s);
  check_comfort(n);
}

// Window statistics against the blockwise recomputation, its events against a recount, and the
// regime against a tracker fed the recomputed K.
template <typename T>
void ObserverRun<T>::check_window(std::uint64_t n, const ReferenceBlock& w,
                                  const ObserverSummary& s) {
  const long double count = w.samples;
  const double rms_u = static_cast<double>(std::sqrt(w.u_sq / count));
  const double rms_x = static_cast<double>(std::sqrt(w.x_sq / count));
  const double p_window = static_cast<double>(w.stuck / count);
  const double window_d[] = {relative(s.rms_u_m_per_s2, rms_u), relative(s.rms_x_m_per_s2, rms_x),
                             relative(s.transmissibility, rms_x / rms_u),
                             relative(s.stick_probability, p_window)};
  for (double d : window_d) {
    window_worst_ = std::fmax(window_worst_, against(d, window_tolerance_));
    if (!(d <= window_tolerance_))
      report_.fail("window statistics vs blockwise", n, d, window_tolerance_);
  }
  if (s.stick_events != w.stick_events || s.slip_events != w.slip_events)
    report_.fail("window stick/slip events vs recount", n, s.stick_events, w.stick_events);
  if (window_.blocks_done >= kBlocks)
    regime_.update(den_hartog_factor(op_.model.kinetic_friction_n, op_.model.mass_kg, rms_u));
  if (s.regime != regime_.regime() || s.regime_known != regime_.known() ||
      s.regime_changes != regime_.changes())
    report_.fail("regime vs a tracker fed the recomputed K", n, s.regime_changes,
                 regime_.changes());
}

// Exponential window and running RMS: mean squares against the long-double recurrence.
// (The observed figure is a root read back and squared in double: a few ulp of double.)
template <typename T>
void ObserverRun<T>::check_recurrences(std::uint64_t n, const ObserverSummary& s) {
  const auto check_recurrence = [&](const char* what, double& worst, double observed_mean,
                                    double mean, double bound) {
    const double tolerance = 2.0 * bound + 8.0 * DBL_EPSILON * std::fabs(mean);
    const double ratio = against(std::fabs(observed_mean - mean), tolerance);
    worst = std::fmax(worst, ratio);
    if (!(ratio <= 1.0)) report_.fail(what, n, observed_mean, mean);
  };
  const RideComfort<T>& comfort = observer_.comfort();
  const ExponentialReference& running_ms = comfort_.running_ms;
  check_recurrence("exponential mean square a_u", exp_worst_,
                   s.exp_rms_u_m_per_s2 * s.exp_rms_u_m_per_s2, static_cast<double>(exp_u_.mean),
                   exp_u_.bound);
  check_recurrence("exponential mean square a_x", exp_worst_,
                   s.exp_rms_x_m_per_s2 * s.exp_rms_x_m_per_s2, static_cast<double>(exp_x_.mean),
                   exp_x_.bound);
  check_recurrence("exponential stuck share", exp_worst_, s.exp_stick_probability,
                   static_cast<double>(exp_stuck_.mean), exp_stuck_.bound);
  check_recurrence("comfort running mean square", comfort_worst_,
                   comfort.seat_running_rms() * comfort.seat_running_rms(),
                   static_cast<double>(running_ms.mean), running_ms.bound);
  check_recurrence("comfort MTVV^2", comfort_worst_, comfort.seat_mtvv() * comfort.seat_mtvv(),
                   running_ms.max_mean, running_ms.max_bound);
}

// Ride comfort against the blockwise recomputation of the same weighted samples.
template <typename T>
void ObserverRun<T>::check_comfort(std::uint64_t n) {
  const RideComfort<T>& comfort = observer_.comfort();
  const long double total = static_cast<long double>(n + 1);  // the reset sample too
  const double comfort_d[] = {
      relative(comfort.floor_weighted_rms(), comfort_.floor_weighted_rms(total)),
      relative(comfort.seat_weighted_rms(), comfort_.seat_weighted_rms(total)),
      relative(comfort.floor_vdv(), comfort_.floor_vdv()),
      relative(comfort.seat_vdv(), comfort_.seat_vdv())};
  for (double d : comfort_d) {
    comfort_worst_ = std::fmax(comfort_worst_, against(d, whole_tolerance_));
    if (!(d <= whole_tolerance_)) report_.fail("ride comfort vs blockwise", n, d, whole_tolerance_);
  }
  if (comfort.seat_peak() != static_cast<double>(comfort_.seat_peak))
    report_.fail("comfort peak vs the recomputation's (same weighted samples)", n,
                 comfort.seat_peak(), static_cast<double>(comfort_.seat_peak));
}

template <typename T>
void ObserverRun<T>::checkpoint(std::uint64_t n) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  Checkpoint c = whole_stream_checkpoint(n, stats_, whole_, seconds, whole_tolerance_, report_);
  c.window_worst = window_worst_;
  c.exp_worst = exp_worst_;
  c.comfort_worst = comfort_worst_;
  report_.row(c, true);
  whole_worst_ = std::fmax(whole_worst_, std::fmax(c.d_t, c.d_p) / whole_tolerance_);
}

// Time keeping at the end: every count is the integer sample count; t = n dt from it.
template <typename T>
void ObserverRun<T>::check_end() {
  const std::uint64_t updates = o_.samples - 1;
  counts_ = observer_.samples() == updates && observer_.comfort().samples() == o_.samples &&
            stats_.samples() == o_.samples && stats_.steps() == updates;
  if (!counts_)
    report_.fail("sample counts (observer, comfort, statistics) vs the integer count", updates,
                 static_cast<double>(observer_.samples()), static_cast<double>(updates));
  // t = n dt is one rounding of the exact product, however long the run: within half an ulp.
  t_end_ = static_cast<double>(updates) * dt_;
  const long double t_exact = static_cast<long double>(updates) * static_cast<long double>(dt_);
  t_error_ = static_cast<double>(std::fabs(static_cast<long double>(t_end_) - t_exact));
  if (!(t_error_ <= 0.5 * std::ldexp(1.0, std::ilogb(t_end_) - 52)))
    report_.fail("t = n dt is off the long-double product by more than half an ulp", updates,
                 t_end_, static_cast<double>(t_exact));
  const Oscillator<T, Law>& seat = observer_.model();
  if (seat.rejected_inputs() != 0 || seat.state_resets() != 0 || seat.event_budget_exhausted() != 0)
    report_.fail(
        "rejected inputs / state resets / event budget hits", updates,
        double(seat.rejected_inputs() + seat.state_resets() + seat.event_budget_exhausted()), 0);
  if (block_checks_ != updates / per_block_)
    report_.fail("block checks", updates, double(block_checks_), 0);
}

template <typename T>
void ObserverRun<T>::print_summary() const {
  const Oscillator<T, Law>& seat = observer_.model();
  const ObserverSummary s = observer_.summary();
  std::printf(
      "soak observer %s: %" PRIu64
      " samples (t = n dt = %.3f s of ride, %.1e s from the "
      "exact product; accumulated t += dt would read %.3f s in double, %.3f s in float), "
      "non-finite outputs %" PRIu64 ", rejected inputs %" PRIu64 ", state resets %" PRIu64
      ", event budget hits %" PRIu64 ", sample counts %s, %" PRIu64 " window blocks checked\n",
      sizeof(T) == 4 ? "float" : "double", o_.samples, t_end_, t_error_, t_double_sum_,
      static_cast<double>(t_float_sum_), non_finite_, seat.rejected_inputs(), seat.state_resets(),
      seat.event_budget_exhausted(), counts_ ? "exact" : "WRONG", block_checks_);
  std::printf(
      "  last window: T_ax %.9f p %.7f K %.4f regime %s (%u changes); exponential T_ax %.9f; "
      "comfort: seat Wk RMS %.6f m/s^2, SEAT %.6f, VDV %.4f m/s^1.75, MTVV %.6f m/s^2\n",
      s.transmissibility, s.stick_probability, s.den_hartog_k, regime_name(s.regime),
      s.regime_changes, s.exp_transmissibility, observer_.comfort().seat_weighted_rms(),
      observer_.comfort().seat_ratio(), observer_.comfort().seat_vdv(),
      observer_.comfort().seat_mtvv());
  std::printf(
      "  worst difference / tolerance: window %.2e (tolerance %.2e relative), exponential and "
      "running RMS %.2e (of twice the running bound), comfort %.2e and whole stream %.2e "
      "(tolerance %.2e relative)\n",
      window_worst_, window_tolerance_, exp_worst_, comfort_worst_, whole_worst_, whole_tolerance_);
}

template <typename T>
int ObserverRun<T>::run() {
  if (!configure()) return 1;
  if (!report_.open_csv(true)) {
    std::fprintf(stderr, "soak: cannot write %s\n", o_.csv);
    return 2;
  }
  std::printf(
      "through the observer: window %u blocks of %u samples, exponential tau %.3g s, %s comfort\n",
      unsigned(kBlocks), per_block_, op_.exponential_time_s,
      op_.weighting == ComfortWeighting::wk ? "Wk" : "Wd");
  report_.header(true);
  reset();
  const std::vector<T>& input = scene_.input;
  const std::uint64_t period = input.size();
  const std::uint64_t every = o_.samples / static_cast<std::uint64_t>(o_.checkpoints);
  std::uint64_t next_checkpoint = every;
  std::uint64_t index = 0;  // into the looped recording
  start_ = std::chrono::steady_clock::now();
  for (std::uint64_t n = 1; n < o_.samples; ++n) {  // time t = n dt: an integer, never accumulated
    if (++index == period) index = 0;
    sample(n, input[index]);
    if (n % per_block_ == 0) check_block(n);  // the integer count says a window block completed
    if (n + 1 == next_checkpoint || n + 1 == o_.samples) {
      next_checkpoint += every;
      checkpoint(n);
    }
  }
  check_end();
  print_summary();
  if (report_.failures() > 0) {
    std::printf("soak FAILED: %" PRIu64 " failed checks, the first: %s\n", report_.failures(),
                report_.first().c_str());
    return 1;
  }
  std::printf("soak passed\n");
  return 0;
}

}  // namespace

template <typename T>
int soak_observer(const Options& o) {
  ObserverRun<T> run(o);
  return run.run();
}

template int soak_observer<float>(const Options& o);
template int soak_observer<double>(const Options& o);

}  // namespace stickslip::soak
