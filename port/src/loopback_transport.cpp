#include "stickslip/port/loopback_transport.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
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
  if (frame.flags & can::kFd)
    return frame.length <= can::kFdMaxLength && !(frame.flags & can::kRemote);
  return frame.length <= can::kClassicMaxLength;
}

class LoopbackEndpoint;

// The process-wide bus: one mutex guards the endpoint list and every endpoint's queue (sends are
// rare enough at 1-10 kHz that one lock is simpler than per-queue locks, and keeps order global).
// The list is intrusive and the queues are fixed rings allocated when an endpoint is made, so
// sending and receiving never allocate.
struct LoopbackBus {
  std::mutex mutex;
  LoopbackEndpoint* first = nullptr;  // open endpoints, linked through LoopbackEndpoint::next_

  static LoopbackBus& instance() {
    static LoopbackBus bus;  // never destroyed before endpoints: function-local, first use
    return bus;
  }
};

class LoopbackEndpoint final : public Transport {
 public:
  explicit LoopbackEndpoint(std::size_t capacity) : ring_(std::max<std::size_t>(capacity, 1)) {}
  ~LoopbackEndpoint() override { close(); }

  TransportStatus open(const std::string& bus_name) noexcept override {
    if (bus_name != "loopback") return TransportStatus::no_such_interface;
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (open_) return TransportStatus::ok;
    next_ = bus.first;
    bus.first = this;
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
    for (LoopbackEndpoint* endpoint = bus.first; endpoint != nullptr; endpoint = endpoint->next_)
      if (endpoint != this) endpoint->deliver(stamped);
    ++counters_.frames_sent;
    return TransportStatus::ok;
  }

  TransportStatus receive(can::Frame& frame, int timeout_ms) noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::unique_lock<std::mutex> lock(bus.mutex);
    if (!open_) return TransportStatus::closed;
    const auto ready = [this] { return count_ > 0 || !open_; };
    if (timeout_ms < 0) {
      arrived_.wait(lock, ready);
    } else if (timeout_ms > 0) {
      arrived_.wait_for(lock, std::chrono::milliseconds(timeout_ms), ready);
    }
    if (!open_) return TransportStatus::closed;
    if (count_ == 0) return TransportStatus::timeout;
    frame = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --count_;
    ++counters_.frames_received;
    return TransportStatus::ok;
  }

  void close() noexcept override {
    LoopbackBus& bus = LoopbackBus::instance();
    std::lock_guard<std::mutex> lock(bus.mutex);
    if (!open_) return;
    for (LoopbackEndpoint** link = &bus.first; *link != nullptr; link = &(*link)->next_) {
      if (*link == this) {
        *link = next_;
        break;
      }
    }
    next_ = nullptr;
    open_ = false;
    head_ = count_ = 0;
    arrived_.notify_all();
  }

  const LoopbackEndpoint* next() const noexcept { return next_; }

  TransportCounters counters() const noexcept override {
    std::lock_guard<std::mutex> lock(LoopbackBus::instance().mutex);
    return counters_;
  }

 private:
  // Called with the bus mutex held.
  void deliver(const can::Frame& frame) noexcept {
    if (!accepts(frame.id)) return;
    if (count_ == ring_.size()) {
      ++counters_.receive_drops;
      return;
    }
    ring_[(head_ + count_) % ring_.size()] = frame;
    ++count_;
    arrived_.notify_one();
  }

  bool accepts(std::uint32_t id) const noexcept {
    if (filters_.empty()) return true;
    for (const ReceiveFilter& filter : filters_)
      if ((id & filter.mask) == (filter.id & filter.mask)) return true;
    return false;
  }

  bool open_ = false;
  LoopbackEndpoint* next_ = nullptr;
  std::vector<ReceiveFilter> filters_;
  std::vector<can::Frame> ring_;  // the bounded receive queue: count_ frames from head_
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  std::condition_variable arrived_;
  TransportCounters counters_;
};

}  // namespace

std::size_t loopback_endpoints() noexcept {
  LoopbackBus& bus = LoopbackBus::instance();
  std::lock_guard<std::mutex> lock(bus.mutex);
  std::size_t count = 0;
  for (const LoopbackEndpoint* endpoint = bus.first; endpoint != nullptr;
       endpoint = endpoint->next())
    ++count;
  return count;
}

std::unique_ptr<Transport> make_loopback_transport() {
  return make_loopback_transport(kLoopbackDefaultQueueFrames);
}

std::unique_ptr<Transport> make_loopback_transport(std::size_t queue_frames) {
  return std::make_unique<LoopbackEndpoint>(queue_frames);
}

}  // namespace stickslip::port
