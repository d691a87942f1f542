#include "soak/report.hpp"

#include <cinttypes>

namespace stickslip::soak {

double relative(double a, double b) {
  const double scale = std::fmax(std::fabs(a), std::fabs(b));
  return scale > 0.0 ? std::fabs(a - b) / scale : 0.0;
}

double against(double difference, double tolerance) {
  return tolerance > 0.0 ? difference / tolerance : (difference == 0.0 ? 0.0 : HUGE_VAL);
}

Report::~Report() {
  if (csv_ != nullptr) std::fclose(csv_);
}

bool Report::open_csv(bool observer) {
  if (options_.csv == nullptr) return true;
  csv_ = std::fopen(options_.csv, "w");
  if (csv_ == nullptr) return false;
  std::fprintf(
      csv_, "samples,T_ax,T_ax_blockwise,p,p_blockwise,rel_diff_T_ax,rel_diff_p,%sns_per_sample\n",
      observer ? "window_worst_over_tol,exp_worst_over_tol,comfort_worst_over_tol," : "");
  return true;
}

void Report::header(bool observer) const {
  std::printf("%14s %12s %12s %10s %10s %9s %9s", "samples", "T_ax", "T_ax_block", "p", "p_block",
              "dT_ax", "dp");
  if (observer) std::printf(" %9s %9s %9s", "win/tol", "exp/tol", "cmf/tol");
  std::printf(" %8s\n", "ns/smp");
}

void Report::row(const Checkpoint& c, bool observer) const {
  std::printf("%14" PRIu64 " %12.9f %12.9f %10.7f %10.7f %9.2e %9.2e", c.samples, c.t_ax,
              c.t_ax_block, c.p, c.p_block, c.d_t, c.d_p);
  if (observer) std::printf(" %9.2e %9.2e %9.2e", c.window_worst, c.exp_worst, c.comfort_worst);
  std::printf(" %8.2f\n", c.ns);
  std::fflush(stdout);
  if (csv_ == nullptr) return;
  std::fprintf(csv_, "%" PRIu64 ",%.17g,%.17g,%.17g,%.17g,%.3e,%.3e,", c.samples, c.t_ax,
               c.t_ax_block, c.p, c.p_block, c.d_t, c.d_p);
  if (observer) std::fprintf(csv_, "%.3e,%.3e,%.3e,", c.window_worst, c.exp_worst, c.comfort_worst);
  std::fprintf(csv_, "%.3f\n", c.ns);
}

void Report::fail(const char* what, std::uint64_t n, double value, double limit) {
  ++failures_;
  if (failures_ <= 5)
    std::printf("soak check failed at sample %" PRIu64 ": %s (%.6g vs %.6g)\n", n, what, value,
                limit);
  if (first_.empty()) first_ = what;
}

}  // namespace stickslip::soak
