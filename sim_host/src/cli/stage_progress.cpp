#include "stage_progress.hpp"

#include <fmt/format.h>

namespace stickslip::host {

namespace {
constexpr std::chrono::seconds kQuietFor{2};  // a run shorter than this prints nothing
constexpr std::chrono::seconds kEvery{2};
}  // namespace

StageProgress::StageProgress(std::ostream& err, const char* what, bool every_stage, bool periodic)
    : err_(err), what_(what), every_stage_(every_stage) {
  if (periodic) watcher_ = std::thread([this] { watch(); });
}

StageProgress::~StageProgress() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  wake_.notify_all();
  if (watcher_.joinable()) watcher_.join();
}

void StageProgress::begin(const std::string& stage) {
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  if (every_stage_) print_locked("");
}

void StageProgress::print_locked(const char* suffix) {
  const double elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count();
  err_ << fmt::format("{}: {}{} ({:.1f} s)\n", what_, stage_, suffix, elapsed_s) << std::flush;
}

void StageProgress::watch() {
  std::unique_lock<std::mutex> lock(mutex_);
  Clock::time_point next = start_ + kQuietFor;
  while (!wake_.wait_until(lock, next, [this] { return done_; })) {
    // With every stage printed already, the periodic line says the same stage is still running.
    if (!stage_.empty()) print_locked(every_stage_ ? ", still running" : "");
    next += kEvery;
  }
}

}  // namespace stickslip::host
