// SIGINT and SIGTERM: as a stop request for the commands that run until stopped (ecu, play),
// and, for every other command, as an interruption that leaves nothing behind. Private to the
// host library.
#pragma once

#include <atomic>
#include <csignal>
#include <cstdint>

#include <signal.h>

namespace stickslip::host {

// Set by the handler while a StopOnSignals lives; the commands pass its address as `stop`.
extern volatile std::sig_atomic_t stop_requested;

// SIGINT and SIGTERM set stop_requested while this lives (no SA_RESTART: a blocking receive or
// sleep returns at once); the previous handlers come back with its end.
class StopOnSignals {
 public:
  // timeout_s > 0: SIGALRM after that long sets stop_requested too (ecu --timeout).
  explicit StopOnSignals(double timeout_s = 0.0);
  ~StopOnSignals();
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {}, old_alarm_ = {};
  bool timer_ = false;
};

// What an interrupted command has done so far, for the one line the handler prints ("N of M
// points done"); total 0: the command does not count points.
extern std::atomic<std::uint64_t> interrupt_points_done;
extern std::atomic<std::uint64_t> interrupt_points_total;

// While this lives, SIGINT and SIGTERM remove every temporary output (remove_live_temporaries),
// print "stickslip: interrupted by SIGINT: ..., nothing written" and exit 128 + the signal, so
// that existing outputs stay as they were. Installed by the executable only (run_cli from
// argv); a StopOnSignals inside it takes the signals over for a command that stops cleanly.
class InterruptCleanup {
 public:
  InterruptCleanup();
  ~InterruptCleanup();
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};

}  // namespace stickslip::host
