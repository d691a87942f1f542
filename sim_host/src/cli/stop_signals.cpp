#include "stop_signals.hpp"

namespace stickslip::host {

volatile std::sig_atomic_t stop_requested = 0;

namespace {

extern "C" void request_stop(int) {
  stop_requested = 1;
}

}  // namespace

StopOnSignals::StopOnSignals() {
  stop_requested = 0;
  struct sigaction action = {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

StopOnSignals::~StopOnSignals() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

}  // namespace stickslip::host
