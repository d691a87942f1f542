// What the soak prints and writes: the checkpoint rows (stdout and the optional CSV) and the failed
// checks, counted, the first few printed and the first one named at the end.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "soak/options.hpp"
#include "soak/oracle.hpp"

namespace stickslip::soak {

// |a - b| over the larger magnitude; 0 when both are 0.
double relative(double a, double b);
// Ratio of a difference to its tolerance: <= 1 passes.
double against(double difference, double tolerance);

struct Checkpoint {
  std::uint64_t samples;
  double t_ax, t_ax_block, p, p_block, d_t, d_p, window_worst, exp_worst, comfort_worst, ns;
};

class Report {
 public:
  explicit Report(const Options& o) : options_(o) {}
  Report(const Report&) = delete;
  Report& operator=(const Report&) = delete;
  ~Report();

  // False if the CSV cannot be opened (no CSV asked for: true).
  bool open_csv(bool observer);
  void header(bool observer) const;
  void row(const Checkpoint& c, bool observer) const;
  // A failed check: remembered (first occurrence printed) and counted.
  void fail(const char* what, std::uint64_t n, double value, double limit);
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

}  // namespace stickslip::soak
