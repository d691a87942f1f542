// Placeholder until the SocketCAN endpoint lands: reports the bus as unsupported.
#include "stickslip/port/socketcan_transport.hpp"

namespace stickslip::port {
namespace {

class UnsupportedTransport final : public Transport {
 public:
  TransportStatus open(const std::string&) noexcept override { return TransportStatus::unsupported; }
  TransportStatus set_filters(const ReceiveFilter*, std::size_t) noexcept override {
    return TransportStatus::unsupported;
  }
  TransportStatus send(const can::Frame&) noexcept override { return TransportStatus::unsupported; }
  TransportStatus receive(can::Frame&, int) noexcept override { return TransportStatus::unsupported; }
  void close() noexcept override {}
  TransportCounters counters() const noexcept override { return {}; }
};

}  // namespace

bool kernel_has_can() noexcept { return false; }

std::unique_ptr<Transport> make_socketcan_transport() { return std::make_unique<UnsupportedTransport>(); }

}  // namespace stickslip::port
