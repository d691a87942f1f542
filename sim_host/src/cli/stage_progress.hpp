// Progress of a command that runs in a few long stages (simulate: read, simulate, write), on
// stderr: with --progress every stage as it starts; on a terminal, the stage still running once
// the command has taken 2 s, and then every 2 s, so a short run stays silent and a long one never
// looks hung.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

namespace stickslip::host {

class StageProgress {
 public:
  // `what` prefixes every line ("simulate"); nothing is printed when neither is set.
  StageProgress(std::ostream& err, const char* what, bool every_stage, bool periodic);
  ~StageProgress();  // stops the periodic line before the command prints its result
  StageProgress(const StageProgress&) = delete;
  StageProgress& operator=(const StageProgress&) = delete;

  void begin(const std::string& stage);

 private:
  using Clock = std::chrono::steady_clock;
  void watch();
  void print_locked(const char* suffix);

  std::ostream& err_;
  const char* what_;
  bool every_stage_;
  Clock::time_point start_ = Clock::now();
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string stage_;
  bool done_ = false;
  std::thread watcher_;
};

}  // namespace stickslip::host
