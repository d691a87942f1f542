#include "stop_signals.hpp"

#include <sys/time.h>
#include <unistd.h>

#include <cstring>

#include "stickslip/host/io/output_file.hpp"

namespace stickslip::host {

volatile std::sig_atomic_t stop_requested = 0;
std::atomic<std::uint64_t> interrupt_points_done{0};
std::atomic<std::uint64_t> interrupt_points_total{0};

namespace {

extern "C" void request_stop(int) {
  stop_requested = 1;
}

// Appends text or a decimal number to a fixed buffer: a signal handler may not format with
// the heap or stdio.
struct SignalSafeLine {
  char text[256];
  std::size_t size = 0;
  void add(const char* part) noexcept {
    for (; *part != '\0' && size + 1 < sizeof text; ++part) text[size++] = *part;
  }
  void add(std::uint64_t value) noexcept {
    char digits[24];
    int count = 0;
    do {
      digits[count++] = static_cast<char>('0' + value % 10);
      value /= 10;
    } while (value != 0);
    while (count > 0 && size + 1 < sizeof text) text[size++] = digits[--count];
  }
};

extern "C" void clean_up_and_exit(int signal_number) {
  remove_live_temporaries();
  SignalSafeLine line;
  line.add("stickslip: interrupted by ");
  line.add(signal_number == SIGINT ? "SIGINT" : "SIGTERM");
  const std::uint64_t total = interrupt_points_total.load();
  if (total > 0) {
    line.add(": ");
    line.add(interrupt_points_done.load());
    line.add(" of ");
    line.add(total);
    line.add(" points done");
  }
  line.add(", nothing written (existing outputs kept)\n");
  ssize_t ignored = ::write(2, line.text, line.size);
  (void)ignored;
  ::_exit(128 + signal_number);
}

}  // namespace

StopOnSignals::StopOnSignals(double timeout_s) {
  stop_requested = 0;
  struct sigaction action = {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
  if (timeout_s > 0.0) {
    sigaction(SIGALRM, &action, &old_alarm_);
    struct itimerval timer = {};
    timer.it_value.tv_sec = static_cast<time_t>(timeout_s);
    timer.it_value.tv_usec =
        static_cast<suseconds_t>((timeout_s - static_cast<double>(timer.it_value.tv_sec)) * 1e6);
    if (timer.it_value.tv_sec == 0 && timer.it_value.tv_usec == 0) timer.it_value.tv_usec = 1;
    setitimer(ITIMER_REAL, &timer, nullptr);
    timer_ = true;
  }
}

StopOnSignals::~StopOnSignals() {
  if (timer_) {
    const struct itimerval off = {};
    setitimer(ITIMER_REAL, &off, nullptr);
    sigaction(SIGALRM, &old_alarm_, nullptr);
  }
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

InterruptCleanup::InterruptCleanup() {
  interrupt_points_done = 0;
  interrupt_points_total = 0;
  struct sigaction action = {};
  action.sa_handler = clean_up_and_exit;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

InterruptCleanup::~InterruptCleanup() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

}  // namespace stickslip::host
