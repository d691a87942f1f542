// SocketCAN endpoint: AF_CAN / CAN_RAW on a named interface (see the header for the contract).
#include "stickslip/port/socketcan_transport.hpp"

#include "stickslip/port/socketcan_frame.hpp"

#include <cerrno>
#include <cstring>
#include <ctime>

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/uio.h>
#include <unistd.h>

namespace stickslip::port {
namespace {

// Older C libraries lack these socket options; the values are the kernel's ABI.
#ifndef SO_RXQ_OVFL
#define SO_RXQ_OVFL 40
#endif

constexpr std::size_t kMaxFilters = CAN_RAW_FILTER_MAX;

std::uint64_t realtime_now_ns() noexcept {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<std::uint64_t>(now.tv_sec) * 1000000000u +
         static_cast<std::uint64_t>(now.tv_nsec);
}

std::int64_t monotonic_now_ms() noexcept {
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1000 + now.tv_nsec / 1000000;
}

int open_raw_socket() noexcept {
  return ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
}

bool socket_family_missing(int error_number) noexcept {
  return error_number == EAFNOSUPPORT || error_number == EPROTONOSUPPORT ||
         error_number == ESOCKTNOSUPPORT;
}

// 1: up, 0: exists but down, -1: no such interface (or the query failed).
int interface_state(int fd, const std::string& name) noexcept {
  ifreq request{};
  std::memcpy(request.ifr_name, name.c_str(), name.size() + 1);  // caller checked the length
  if (::ioctl(fd, SIOCGIFFLAGS, &request) != 0) return -1;
  return (request.ifr_flags & IFF_UP) != 0 ? 1 : 0;
}

class SocketCanTransport final : public Transport {
 public:
  explicit SocketCanTransport(const SocketCanOptions& options) : options_(options) {}
  ~SocketCanTransport() override { close(); }
  SocketCanTransport(const SocketCanTransport&) = delete;
  SocketCanTransport& operator=(const SocketCanTransport&) = delete;

  TransportStatus open(const std::string& bus_name) noexcept override {
    close();
    counters_ = {};
    if (bus_name.empty() || bus_name.size() >= IFNAMSIZ) return TransportStatus::invalid_argument;
    const int fd = open_raw_socket();
    if (fd < 0) {
      return socket_family_missing(errno) ? TransportStatus::unsupported
                                          : TransportStatus::io_error;
    }
    const TransportStatus status = configure(fd, bus_name);
    if (status != TransportStatus::ok) {
      ::close(fd);
      return status;
    }
    fd_ = fd;
    return TransportStatus::ok;
  }

  TransportStatus set_filters(const ReceiveFilter* filters, std::size_t count) noexcept override {
    if (fd_ < 0) return TransportStatus::closed;
    if (count > kMaxFilters || (count > 0 && filters == nullptr)) {
      return TransportStatus::invalid_argument;
    }
    can_filter table[kMaxFilters];
    std::size_t used = count;
    if (count == 0) {  // accept everything: one filter with an empty mask
      table[0] = can_filter{0, 0};
      used = 1;
    }
    for (std::size_t n = 0; n < count; ++n) {
      // The rule (id & mask) == (filter.id & mask) on the identifier bits alone: standard and
      // extended frames with matching identifier bits both pass (no flag bits in the mask).
      table[n].can_id = filters[n].id & CAN_EFF_MASK;
      table[n].can_mask = filters[n].mask & CAN_EFF_MASK;
    }
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, table,
                     static_cast<socklen_t>(used * sizeof(can_filter))) != 0) {
      return errno == EINVAL ? TransportStatus::invalid_argument : TransportStatus::io_error;
    }
    return TransportStatus::ok;
  }

  TransportStatus send(const can::Frame& frame) noexcept override {
    const TransportStatus status = send_frame(frame);
    if (status == TransportStatus::ok) {
      ++counters_.frames_sent;
    } else {
      ++counters_.send_failures;
    }
    return status;
  }

  TransportStatus receive(can::Frame& frame, int timeout_ms) noexcept override {
    if (fd_ < 0) return TransportStatus::closed;
    const std::int64_t deadline_ms = timeout_ms > 0 ? monotonic_now_ms() + timeout_ms : 0;
    for (;;) {
      const TransportStatus status = read_frame(frame);
      if (status != TransportStatus::timeout) return status;  // a frame, or a failed read
      int wait_ms = timeout_ms;
      if (timeout_ms > 0) {
        const std::int64_t left = deadline_ms - monotonic_now_ms();
        if (left <= 0) return TransportStatus::timeout;
        wait_ms = static_cast<int>(left);
      } else if (timeout_ms == 0) {
        return TransportStatus::timeout;
      }
      pollfd watch{fd_, POLLIN, 0};
      const int ready = ::poll(&watch, 1, wait_ms);
      if (ready < 0) {
        if (errno == EINTR) continue;
        return TransportStatus::io_error;
      }
      if (ready == 0) return TransportStatus::timeout;
      if ((watch.revents & POLLNVAL) != 0) return TransportStatus::closed;
      // POLLIN or POLLERR: the next read returns the frame or the pending socket error.
    }
  }

  void close() noexcept override {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  TransportCounters counters() const noexcept override { return counters_; }

 private:
  TransportStatus configure(int fd, const std::string& name) noexcept {
    const unsigned index = ::if_nametoindex(name.c_str());
    if (index == 0) return TransportStatus::no_such_interface;
    if (interface_state(fd, name) != 1) return TransportStatus::no_such_interface;

    const int on = 1;
    // FD frames must be seen whole; a kernel without CAN FD (ENOPROTOOPT) cannot deliver any,
    // so the endpoint still works for classic frames.
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0 &&
        errno != ENOPROTOOPT) {
      return TransportStatus::io_error;
    }
    const can_err_mask_t every_error = CAN_ERR_MASK;
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &every_error, sizeof every_error) != 0) {
      return TransportStatus::io_error;
    }
    if (::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) != 0 &&
        ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0) {
      return TransportStatus::io_error;
    }
    if (::setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) != 0)
      return TransportStatus::io_error;
    if (options_.receive_buffer_bytes > 0 &&
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &options_.receive_buffer_bytes,
                     sizeof options_.receive_buffer_bytes) != 0) {
      return TransportStatus::io_error;
    }
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(index);
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      return (errno == ENODEV || errno == ENETDOWN || errno == ENXIO)
                 ? TransportStatus::no_such_interface
                 : TransportStatus::io_error;
    }
    return TransportStatus::ok;
  }

  TransportStatus send_frame(const can::Frame& frame) const noexcept {
    if (fd_ < 0) return TransportStatus::closed;
    canfd_frame raw{};
    std::size_t size = 0;
    const TransportStatus encoded = encode_socketcan_write(frame, raw, size);
    if (encoded != TransportStatus::ok) return encoded;
    for (;;) {
      const ssize_t written = ::send(fd_, &raw, size, MSG_DONTWAIT);
      if (written == static_cast<ssize_t>(size)) return TransportStatus::ok;
      if (written >= 0) return TransportStatus::io_error;  // a short write of a datagram
      switch (errno) {
        case EINTR:
          continue;
        case EAGAIN:
#if EWOULDBLOCK != EAGAIN
        case EWOULDBLOCK:
#endif
        case ENOBUFS:
          return TransportStatus::buffer_full;
        case EINVAL:
          return TransportStatus::invalid_argument;  // e.g. FD on a classic-MTU bus
        case ENETDOWN:
          return TransportStatus::interface_down;
        case ENODEV:
        case ENXIO:
          return TransportStatus::no_such_interface;
        default:
          return TransportStatus::io_error;
      }
    }
  }

  // ok with a frame, timeout when nothing is queued, or a failure.
  TransportStatus read_frame(can::Frame& frame) noexcept {
    canfd_frame raw{};
    iovec buffer{&raw, sizeof raw};
    // Room for a timespec timestamp and the 32-bit drop counter.
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(timeval)) +
                                  CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr message{};
    message.msg_iov = &buffer;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof control;
    ssize_t bytes = -1;
    for (;;) {
      bytes = ::recvmsg(fd_, &message, MSG_DONTWAIT);
      if (bytes >= 0 || errno != EINTR) break;
    }
    if (bytes < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return TransportStatus::timeout;
      if (errno == EBADF) return TransportStatus::closed;
      if (errno == ENETDOWN) return TransportStatus::interface_down;
      if (errno == ENODEV) return TransportStatus::no_such_interface;
      return TransportStatus::io_error;
    }
    std::uint64_t timestamp_ns = 0;
    for (cmsghdr* item = CMSG_FIRSTHDR(&message); item != nullptr;
         item = CMSG_NXTHDR(&message, item)) {
      if (item->cmsg_level != SOL_SOCKET) continue;
      if (item->cmsg_type == SO_TIMESTAMPNS) {
        timespec stamp{};
        std::memcpy(&stamp, CMSG_DATA(item), sizeof stamp);
        timestamp_ns = static_cast<std::uint64_t>(stamp.tv_sec) * 1000000000u +
                       static_cast<std::uint64_t>(stamp.tv_nsec);
      } else if (item->cmsg_type == SO_TIMESTAMP) {
        timeval stamp{};
        std::memcpy(&stamp, CMSG_DATA(item), sizeof stamp);
        timestamp_ns = static_cast<std::uint64_t>(stamp.tv_sec) * 1000000000u +
                       static_cast<std::uint64_t>(stamp.tv_usec) * 1000u;
      } else if (item->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t dropped = 0;  // the socket's running total
        std::memcpy(&dropped, CMSG_DATA(item), sizeof dropped);
        if (dropped > counters_.receive_drops) counters_.receive_drops = dropped;
      }
    }
    if (!decode_socketcan_read(raw, static_cast<std::size_t>(bytes),
                               (message.msg_flags & MSG_TRUNC) != 0, frame)) {
      ++counters_.malformed_reads;
      return TransportStatus::io_error;
    }
    frame.timestamp_ns = timestamp_ns != 0 ? timestamp_ns : realtime_now_ns();
    ++counters_.frames_received;
    return TransportStatus::ok;
  }

  SocketCanOptions options_;
  int fd_ = -1;
  TransportCounters counters_;
};

}  // namespace

bool is_fd_length(unsigned length) noexcept {
  return length <= 8 || length == 12 || length == 16 || length == 20 || length == 24 ||
         length == 32 || length == 48 || length == 64;
}

bool decode_socketcan_read(const canfd_frame& raw, std::size_t size, bool truncated,
                           can::Frame& frame) noexcept {
  const bool classic = size == CAN_MTU && raw.len <= CAN_MAX_DLEN;
  const bool fd = size == CANFD_MTU && is_fd_length(raw.len);
  if (truncated || (!classic && !fd)) return false;
  can::Frame decoded;
  if ((raw.can_id & CAN_ERR_FLAG) != 0) {
    decoded.id = raw.can_id & CAN_ERR_MASK;
    decoded.flags = can::kErrorFrame;
  } else if ((raw.can_id & CAN_EFF_FLAG) != 0) {
    decoded.id = raw.can_id & CAN_EFF_MASK;
    decoded.flags = can::kExtendedId;
  } else {
    decoded.id = raw.can_id & CAN_SFF_MASK;
  }
  if (fd) {
    decoded.flags |= can::kFd;  // an FD frame has no remote form
  } else if ((raw.can_id & CAN_RTR_FLAG) != 0) {
    decoded.flags |= can::kRemote;  // length: the requested DLC, no data
  }
  decoded.length = raw.len;
  if ((decoded.flags & can::kRemote) == 0) std::memcpy(decoded.data, raw.data, raw.len);
  frame = decoded;
  return true;
}

TransportStatus encode_socketcan_write(const can::Frame& frame, canfd_frame& raw,
                                       std::size_t& size) noexcept {
  if ((frame.flags & can::kErrorFrame) != 0) return TransportStatus::invalid_argument;
  const bool extended = (frame.flags & can::kExtendedId) != 0;
  const bool remote = (frame.flags & can::kRemote) != 0;
  const bool fd = (frame.flags & can::kFd) != 0;
  if (frame.id > (extended ? can::kExtendedIdMask : can::kStandardIdMask))
    return TransportStatus::invalid_argument;
  if (fd ? (remote || !is_fd_length(frame.length)) : frame.length > can::kClassicMaxLength) {
    return TransportStatus::invalid_argument;
  }
  raw = canfd_frame{};
  raw.can_id = frame.id | (extended ? CAN_EFF_FLAG : 0u) | (remote ? CAN_RTR_FLAG : 0u);
  raw.len = frame.length;
  if (!remote) std::memcpy(raw.data, frame.data, frame.length);
  size = fd ? CANFD_MTU : CAN_MTU;  // a can_frame is a canfd_frame's prefix
  return TransportStatus::ok;
}

bool kernel_has_can() noexcept {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

bool can_interface_is_up(const std::string& interface_name) noexcept {
  if (interface_name.empty() || interface_name.size() >= IFNAMSIZ) return false;
  const int fd = open_raw_socket();
  if (fd < 0) return false;
  const bool up = interface_state(fd, interface_name) == 1;
  ::close(fd);
  return up;
}

std::unique_ptr<Transport> make_socketcan_transport() {
  return make_socketcan_transport(SocketCanOptions{});
}

std::unique_ptr<Transport> make_socketcan_transport(const SocketCanOptions& options) {
  return std::make_unique<SocketCanTransport>(options);
}

}  // namespace stickslip::port
