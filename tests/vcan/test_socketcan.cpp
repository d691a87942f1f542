// The SocketCAN endpoint (port/src/socketcan_transport.cpp) against a real kernel.
//
// SocketCanVcan needs AF_CAN and an up vcan interface (STICKSLIP_VCAN_IFACE, default vcan0), and
// can-utils for the interplay tests. These hosts have no AF_CAN, so CTest runs this group only
// inside the qemu guest (tests/vcan: the vcan.guest test), never as a host test that could pass
// without a bus. SocketCanWithoutInterface holds for every kernel and runs on the host too.
#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/port/socketcan_transport.hpp"
#include "stickslip/port/transport.hpp"
#include "support/host_test_support.hpp"
// Last: CppUTest redefines `new` for its leak detection.
#include "CppUTest/TestHarness.h"

extern char** environ;

namespace can = stickslip::can;
namespace port = stickslip::port;
using port::TransportStatus;

namespace {

std::string interface_name() {
  const char* name = std::getenv("STICKSLIP_VCAN_IFACE");
  return name != nullptr && *name != '\0' ? name : "vcan0";
}

std::uint64_t realtime_ns() {
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<std::uint64_t>(now.tv_sec) * 1000000000u +
         static_cast<std::uint64_t>(now.tv_nsec);
}

can::Frame classic(std::uint32_t id, std::vector<std::uint8_t> data, std::uint8_t flags = 0) {
  can::Frame frame;
  frame.id = id;
  frame.flags = flags;
  frame.length = static_cast<std::uint8_t>(data.size());
  for (std::size_t n = 0; n < data.size(); ++n) frame.data[n] = data[n];
  return frame;
}

void check_status(TransportStatus expected, TransportStatus actual) {
  STRCMP_EQUAL(port::transport_status_name(expected), port::transport_status_name(actual));
}

void check_frame(const can::Frame& expected, const can::Frame& actual) {
  UNSIGNED_LONGS_EQUAL(expected.id, actual.id);
  UNSIGNED_LONGS_EQUAL(expected.flags, actual.flags);
  UNSIGNED_LONGS_EQUAL(expected.length, actual.length);
  MEMCMP_EQUAL(expected.data, actual.data, expected.length);
}

// Runs a shell command line under `timeout`; its exit status.
int run_guarded(const std::string& command) {
  const std::string guarded = "timeout 20 " + command;
  const int status = std::system(guarded.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A child process whose stdout we read (for candump).
class Child {
 public:
  explicit Child(const std::vector<std::string>& argv) {
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
    std::vector<char*> args;
    for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
    args.push_back(nullptr);
    if (::posix_spawnp(&pid_, args[0], &actions, nullptr, args.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    out_fd_ = pipe_fds[0];
  }
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
    if (out_fd_ >= 0) ::close(out_fd_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  bool started() const { return pid_ > 0; }
  // Reads what is available within timeout_ms (appends to out); false at end of output.
  bool read_some(std::string& out, int timeout_ms) {
    pollfd watch{out_fd_, POLLIN, 0};
    if (::poll(&watch, 1, timeout_ms) <= 0) return true;
    char buffer[512];
    const ssize_t got = ::read(out_fd_, buffer, sizeof buffer);
    if (got <= 0) return false;
    out.append(buffer, static_cast<std::size_t>(got));
    return true;
  }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
};

}  // namespace

TEST_GROUP(SocketCanWithoutInterface){};

TEST(SocketCanWithoutInterface, EveryCallOnAnUnopenedEndpointSaysClosed) {
  auto endpoint = port::make_socketcan_transport();
  can::Frame frame = classic(0x123, {1});
  check_status(TransportStatus::closed, endpoint->send(frame));
  check_status(TransportStatus::closed, endpoint->receive(frame, 0));
  check_status(TransportStatus::closed, endpoint->set_filters(nullptr, 0));
  UNSIGNED_LONGLONGS_EQUAL(1, endpoint->counters().send_failures);
}

TEST(SocketCanWithoutInterface, OpenSaysUnsupportedWithoutAfCanElseNoSuchInterface) {
  auto endpoint = port::make_socketcan_transport();
  check_status(TransportStatus::invalid_argument, endpoint->open(""));
  check_status(TransportStatus::invalid_argument, endpoint->open("a-name-longer-than-15"));
  const TransportStatus status = endpoint->open("nosuchcan7");
  check_status(
      port::kernel_has_can() ? TransportStatus::no_such_interface : TransportStatus::unsupported,
      status);
  if (!port::kernel_has_can()) {
    CHECK_FALSE(port::can_interface_is_up("vcan0"));
    STRCMP_EQUAL("loopback", port::default_bus_name().c_str());
  }
}

TEST_GROUP(SocketCanVcan) {
  std::unique_ptr<port::Transport> sender = port::make_socketcan_transport();
  std::unique_ptr<port::Transport> receiver = port::make_socketcan_transport();
  void setup() override {
    CHECK_TEXT(port::kernel_has_can(),
               "this kernel has no AF_CAN: run this group in the vcan guest");
    check_status(TransportStatus::ok, sender->open(interface_name()));
    check_status(TransportStatus::ok, receiver->open(interface_name()));
  }
  can::Frame receive_one(int timeout_ms = 2000) {
    can::Frame frame;
    check_status(TransportStatus::ok, receiver->receive(frame, timeout_ms));
    return frame;
  }
  void check_nothing_more() {
    can::Frame frame;
    check_status(TransportStatus::timeout, receiver->receive(frame, 100));
  }
};

TEST(SocketCanVcan, TheKernelHasCanAndTheDefaultBusIsVcan0) {
  CHECK_TRUE(port::can_interface_is_up(interface_name()));
  if (interface_name() == "vcan0") STRCMP_EQUAL("vcan0", port::default_bus_name().c_str());
}

TEST(SocketCanVcan, ClassicFrameGoesFromOneEndpointToTheOtherWithATimestamp) {
  const can::Frame sent = classic(0x123, {0xDE, 0xAD, 0xBE, 0xEF});
  const std::uint64_t before = realtime_ns();
  check_status(TransportStatus::ok, sender->send(sent));
  const can::Frame got = receive_one();
  const std::uint64_t after = realtime_ns();
  check_frame(sent, got);
  CHECK_TRUE(got.timestamp_ns >= before);
  CHECK_TRUE(got.timestamp_ns <= after);
  // The sender does not receive its own frame.
  can::Frame own;
  check_status(TransportStatus::timeout, sender->receive(own, 100));
  UNSIGNED_LONGLONGS_EQUAL(1, sender->counters().frames_sent);
  UNSIGNED_LONGLONGS_EQUAL(1, receiver->counters().frames_received);
  UNSIGNED_LONGLONGS_EQUAL(0, receiver->counters().receive_drops);
  UNSIGNED_LONGLONGS_EQUAL(0, receiver->counters().malformed_reads);
}

TEST(SocketCanVcan, ExtendedAndRemoteFramesKeepTheirKind) {
  const can::Frame extended = classic(0x1ABCDEF0, {1, 2, 3, 4, 5, 6, 7, 8}, can::kExtendedId);
  can::Frame remote = classic(0x321, {}, can::kRemote);
  remote.length = 4;  // the requested DLC
  check_status(TransportStatus::ok, sender->send(extended));
  check_status(TransportStatus::ok, sender->send(remote));
  check_frame(extended, receive_one());
  const can::Frame got = receive_one();
  UNSIGNED_LONGS_EQUAL(0x321, got.id);
  UNSIGNED_LONGS_EQUAL(can::kRemote, got.flags);
  UNSIGNED_LONGS_EQUAL(4, got.length);
}

TEST(SocketCanVcan, FdFramesArriveWholeAndMarkedFd) {
  can::Frame fd = classic(0x456, {}, can::kFd);
  fd.length = 64;
  for (int n = 0; n < 64; ++n) fd.data[n] = static_cast<std::uint8_t>(n * 3 + 1);
  check_status(TransportStatus::ok, sender->send(fd));
  can::Frame short_fd = classic(0x457, {9, 8, 7}, can::kFd);
  check_status(TransportStatus::ok, sender->send(short_fd));
  check_frame(fd, receive_one());
  check_frame(short_fd, receive_one());  // FD even when it would fit a classic frame
}

TEST(SocketCanVcan, ReceiveFiltersPassOnlyMatchingIdsUntilCleared) {
  const port::ReceiveFilter filter{0x100, 0x7F0};
  check_status(TransportStatus::ok, receiver->set_filters(&filter, 1));
  for (std::uint32_t id : {0x105u, 0x200u, 0x10Fu, 0x0F0u}) {
    check_status(TransportStatus::ok, sender->send(classic(id, {static_cast<std::uint8_t>(id)})));
  }
  UNSIGNED_LONGS_EQUAL(0x105, receive_one().id);
  UNSIGNED_LONGS_EQUAL(0x10F, receive_one().id);
  check_nothing_more();
  check_status(TransportStatus::ok, receiver->set_filters(nullptr, 0));
  check_status(TransportStatus::ok, sender->send(classic(0x200, {})));
  UNSIGNED_LONGS_EQUAL(0x200, receive_one().id);
  check_status(TransportStatus::invalid_argument, receiver->set_filters(&filter, 100000));
}

TEST(SocketCanVcan, ReceiveTimesOutAfterTheTimeoutAndPollsWithZero) {
  can::Frame frame;
  auto start = std::chrono::steady_clock::now();
  check_status(TransportStatus::timeout, receiver->receive(frame, 0));
  const auto poll_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::steady_clock::now() - start)
                           .count();
  CHECK_TRUE(poll_ms < 100);
  start = std::chrono::steady_clock::now();
  check_status(TransportStatus::timeout, receiver->receive(frame, 300));
  const auto waited_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  CHECK_TRUE(waited_ms >= 299);
  CHECK_TRUE(waited_ms < 3000);
}

TEST(SocketCanVcan, TimestampsFollowTheSendingTimes) {
  check_status(TransportStatus::ok, sender->send(classic(0x10, {1})));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  check_status(TransportStatus::ok, sender->send(classic(0x10, {2})));
  const can::Frame first = receive_one();
  const can::Frame second = receive_one();
  CHECK_TRUE(second.timestamp_ns > first.timestamp_ns);
  CHECK_TRUE(second.timestamp_ns - first.timestamp_ns >= 45000000u);
}

TEST(SocketCanVcan, FramesTheBusCannotCarryAreRefusedAndCounted) {
  can::Frame frame = classic(0x123, {});
  frame.length = 9;
  check_status(TransportStatus::invalid_argument, sender->send(frame));
  check_status(TransportStatus::invalid_argument, sender->send(classic(0x800, {1})));
  check_status(TransportStatus::invalid_argument,
               sender->send(classic(0x20000000, {1}, can::kExtendedId)));
  check_status(TransportStatus::invalid_argument,
               sender->send(classic(0x4, {0, 4}, can::kErrorFrame)));
  can::Frame fd = classic(0x123, {}, can::kFd);
  fd.length = 13;  // no DLC says 13
  check_status(TransportStatus::invalid_argument, sender->send(fd));
  UNSIGNED_LONGLONGS_EQUAL(5, sender->counters().send_failures);
  UNSIGNED_LONGLONGS_EQUAL(0, sender->counters().frames_sent);
  check_nothing_more();
}

TEST(SocketCanVcan, AFloodOverASmallReceiveBufferIsCountedAsDrops) {
  port::SocketCanOptions options;
  options.receive_buffer_bytes = 1;  // the kernel raises it to its minimum (a few frames)
  auto small = port::make_socketcan_transport(options);
  check_status(TransportStatus::ok, small->open(interface_name()));
  const int flood = 2000;
  int sent = 0;
  while (sent < flood) {
    const TransportStatus status = sender->send(classic(0x321, {static_cast<std::uint8_t>(sent)}));
    if (status == TransportStatus::buffer_full) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    check_status(TransportStatus::ok, status);
    ++sent;
  }
  can::Frame frame;
  std::uint64_t read = 0;
  while (small->receive(frame, 200) == TransportStatus::ok) ++read;
  // The kernel stamps its drop count on the frames queued after the drops: one more frame
  // brings the count once the flood has been read.
  check_status(TransportStatus::ok, sender->send(classic(0x322, {0xEE})));
  check_status(TransportStatus::ok, small->receive(frame, 2000));
  UNSIGNED_LONGS_EQUAL(0x322, frame.id);
  ++read;
  const port::TransportCounters counters = small->counters();
  UNSIGNED_LONGLONGS_EQUAL(read, counters.frames_received);
  CHECK_TRUE(read > 1);
  CHECK_TRUE(counters.receive_drops > 0);
  UNSIGNED_LONGLONGS_EQUAL(static_cast<std::uint64_t>(flood) + 1, read + counters.receive_drops);
  std::printf("\n  flood: %d sent, %llu read, %llu dropped (SO_RXQ_OVFL)\n", flood,
              static_cast<unsigned long long>(read),
              static_cast<unsigned long long>(counters.receive_drops));
}

TEST(SocketCanVcan, ADownOrMissingInterfaceIsNoSuchInterface) {
  auto endpoint = port::make_socketcan_transport();
  check_status(TransportStatus::no_such_interface, endpoint->open("nosuchcan7"));
  const char* down = std::getenv("STICKSLIP_VCAN_DOWN_IFACE");  // the guest creates one, left down
  if (down != nullptr && *down != '\0') {
    CHECK_TEXT(::if_nametoindex(down) != 0, "the down interface should exist");
    check_status(TransportStatus::no_such_interface, endpoint->open(down));
    CHECK_FALSE(port::can_interface_is_up(down));
  }
}

TEST(SocketCanVcan, CansendFramesAndErrorFramesReachOurEndpoint) {
  LONGS_EQUAL(0, run_guarded("cansend " + interface_name() + " 1F334455#1122334455667788"));
  check_frame(
      classic(0x1F334455, {0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88}, can::kExtendedId),
      receive_one());
  LONGS_EQUAL(0, run_guarded("cansend " + interface_name() + " 123##1AABBCCDDEEFF001122334455"));
  check_frame(
      classic(0x123, {0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF, 0x00, 0x11, 0x22, 0x33, 0x44, 0x55},
              can::kFd),
      receive_one());
  // An error frame (CAN_ERR_FLAG | CAN_ERR_CRTL) as a driver would report it.
  LONGS_EQUAL(0, run_guarded("cansend " + interface_name() + " 20000004#0004000000000000"));
  check_frame(classic(0x4, {0, 4, 0, 0, 0, 0, 0, 0}, can::kErrorFrame), receive_one());
  check_nothing_more();
}

TEST(SocketCanVcan, CandumpSeesWhatWeSendInTheLogFormatWeRead) {
  Child candump({"timeout", "30", "candump", "-L", interface_name()});
  CHECK_TRUE(candump.started());
  // candump needs a moment to bind: send a sync frame until one shows up (late copies of it may
  // follow, always before the frames under test, because candump prints in order).
  const can::Frame sync = classic(0x7F0, {0x55});
  std::string out;
  for (int attempt = 0; attempt < 100 && out.find('\n') == std::string::npos; ++attempt) {
    check_status(TransportStatus::ok, sender->send(sync));
    if (!candump.read_some(out, 100)) break;
  }
  CHECK_TEXT(out.find('\n') != std::string::npos, "candump printed nothing");
  const can::Frame first = classic(0x0AB, {0x01, 0x02, 0x03});
  can::Frame second = classic(0x456, {}, can::kFd);
  second.length = 16;
  for (int n = 0; n < 16; ++n) second.data[n] = static_cast<std::uint8_t>(0xF0 + n);
  check_status(TransportStatus::ok, sender->send(first));
  check_status(TransportStatus::ok, sender->send(second));
  for (int attempt = 0; attempt < 100 && out.find("456##") == std::string::npos; ++attempt) {
    if (!candump.read_some(out, 100)) break;
  }
  while (!out.empty() && out.back() != '\n' && candump.read_some(out, 100)) {
  }
  stickslip::test::TempDir dir;
  const std::string path = dir.file("candump.log");
  stickslip::test::write_text(path, out);
  const std::vector<stickslip::host::LoggedFrame> logged = stickslip::host::read_candump_log(path);
  CHECK_TRUE(logged.size() >= 3);
  const std::size_t count = logged.size();
  for (std::size_t n = 0; n + 2 < count; ++n) check_frame(sync, logged[n].frame);
  STRCMP_EQUAL(interface_name().c_str(), logged[count - 2].interface.c_str());
  check_frame(first, logged[count - 2].frame);
  check_frame(second, logged[count - 1].frame);
  CHECK_TRUE(logged[count - 1].time_us >= logged[count - 2].time_us);
}
