// SIGINT and SIGTERM as a stop request for the commands that run until stopped (ecu, play).
// Private to the host library.
#pragma once

#include <csignal>

#include <signal.h>

namespace stickslip::host {

// Set by the handler while a StopOnSignals lives; the commands pass its address as `stop`.
extern volatile std::sig_atomic_t stop_requested;

// SIGINT and SIGTERM set stop_requested while this lives (no SA_RESTART: a blocking receive or
// sleep returns at once); the previous handlers come back with its end.
class StopOnSignals {
 public:
  StopOnSignals();
  ~StopOnSignals();
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct sigaction old_int_ = {}, old_term_ = {};
};

}  // namespace stickslip::host
