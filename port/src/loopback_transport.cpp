#include "stickslip/port/loopback_transport.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <vector>

namespace stickslip::port {
namespace {

std::uint64_t steady_now_ns() noexcept {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

bool frame_is_valid(const can::Frame& frame) noexcept {
  const std::uint32_t id_mask =
      (frame.flags & can::kExtendedId) ? can::kExtendedIdMask : can::kStandardIdMask;
  if ((frame.id & ~id_mask) != 0) return false;
  if (frame.flags & can::kFd) return frame.length <= can::kFdMaxLength && !(frame.flags & can::kRemote);
  return frame.length <= can::kClassicMaxLength;
}

class LoopbackEndpoint;

// The process-wide bus: one mutex guards the endpoint list and every endpoint's queue (sends are
// rare enough at 1-10 kHz that one lock is simpler than per-queue locks, and keeps order global).
struct LoopbackBus {
  std::mutex mutex;
  std::vector<LoopbackEndpoint*> endpoints;

  static LoopbackBus& instance() {
    static LoopbackBus bus;  // never destroyed before endpoints: function-local, first use
    return bus;
  }
};

class LoopbackEndpoint final : public Transport {
 public:
  explicit LoopbackEndpoint(std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {}
  ~LoopbackEndpoint() override { close(); }

  TransportStatus open(const std::string& bus_name) noexcept override {
    if (bus_name != "loopback") return TransportStatus::no_such_interface;
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (open_) return TransportStatus::ok;
    try {
      bus.endpoints.push_back(this);
    } catch (...) {
      return TransportStatus::io_error;
    }
    open_ = true;
    return TransportStatus::ok;
  }

  TransportStatus set_filters(const ReceiveFilter* filters, std::size_t count) noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (!open_) return TransportStatus::closed;
    if (count > 0 && filters == nullptr) return TransportStatus::invalid_argument;
    try {
      filters_.assign(filters, filters + count);
    } catch (...) {
      return TransportStatus::io_error;
    }
    return TransportStatus::ok;
  }

  TransportStatus send(const can::Frame& frame) noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (!open_) {
      ++counters_.send_failures;
      return TransportStatus::closed;
    }
    if (!frame_is_valid(frame)) {
      ++counters_.send_failures;
      return TransportStatus::invalid_argument;
    }
    can::Frame stamped = frame;
    stamped.timestamp_ns = steady_now_ns();
    for (LoopbackEndpoint* endpoint : bus.endpoints)
      if (endpoint != this) endpoint->deliver(stamped);
    ++counters_.frames_sent;
    return TransportStatus::ok;
  }

  TransportStatus receive(can::Frame& frame, int timeout_ms) noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::unique_lock<std::mutex> lock(bus.mutex);
    if (!open_) return TransportStatus::closed;
    const auto ready = [this] { return !queue_.empty() || !open_; };
    if (timeout_ms < 0) {
      arrived_.wait(lock, ready);
    } else if (timeout_ms > 0) {
      arrived_.wait_for(lock, std::chrono::milliseconds(timeout_ms), ready);
    }
    if (!open_) return TransportStatus::closed;
    if (queue_.empty()) return TransportStatus::timeout;
    frame = queue_.front();
    queue_.pop_front();
    ++counters_.frames_received;
    return TransportStatus::ok;
  }

  void close() noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (!open_) return;
    bus.endpoints.erase(std::remove(bus.endpoints.begin(), bus.endpoints.end(), this),
                        bus.endpoints.end());
    open_ = false;
    queue_.clear();
    arrived_.notify_all();
  }

  TransportCounters counters() const noexcept override {
    std::lock_guard<std::mutex> lock(LoopbackBus::instance().mutex);
    return counters_;
  }

 private:
  // Called with the bus mutex held.
  void deliver(const can::Frame& frame) noexcept {
    if (!accepts(frame.id)) return;
    if (queue_.size() >= capacity_) {
      ++counters_.receive_drops;
      return;
    }
    try {
      queue_.push_back(frame);
    } catch (...) {
      ++counters_.receive_drops;
      return;
    }
    arrived_.notify_one();
  }

  bool accepts(std::uint32_t id) const noexcept {
    if (filters_.empty()) return true;
    for (const ReceiveFilter& filter : filters_)
      if ((id & filter.mask) == (filter.id & filter.mask)) return true;
    return false;
  }

  const std::size_t capacity_;
  bool open_ = false;
  std::vector<ReceiveFilter> filters_;
  std::deque<can::Frame> queue_;
  std::condition_variable arrived_;
  TransportCounters counters_;
};

}  // namespace

std::unique_ptr<Transport> make_loopback_transport() {
  return make_loopback_transport(kLoopbackDefaultQueueFrames);
}

std::unique_ptr<Transport> make_loopback_transport(std::size_t queue_frames) {
  return std::make_unique<LoopbackEndpoint>(queue_frames);
}

}  // namespace stickslip::port
