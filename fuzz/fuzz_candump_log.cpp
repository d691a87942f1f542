// The candump log reader on arbitrary bytes: it either returns frames that keep the format's
// promises (ids within their width, classic frames of at most 8 bytes, FD frames of a length a
// DLC can express, interface names of 1..15 printable ASCII characters other than space) or throws
// HostError naming the line; nothing else. What it accepts, the writer writes back and the reader
// reads back to the same frames (the log round trip replay and record rely on).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/candump_log.hpp"

#include "fuzz_support.hpp"

namespace {

using stickslip::fuzz::check;

using stickslip::host::LoggedFrame;
namespace can = stickslip::can;

// The writer renames a temporary file into place: it needs a real directory.
const std::string& round_trip_path() {
  static const std::string path = [] {
    char directory[] = "/tmp/stickslip-fuzz-candump-XXXXXX";
    if (mkdtemp(directory) == nullptr) std::abort();
    return std::string(directory) + "/round-trip.log";
  }();
  return path;
}

bool valid_fd_length(unsigned length) {
  return length <= 8 || length == 12 || length == 16 || length == 20 || length == 24 ||
         length == 32 || length == 48 || length == 64;
}

bool same_frame(const LoggedFrame& a, const LoggedFrame& b) {
  if (a.time_us != b.time_us || a.interface != b.interface) return false;
  if (a.frame.id != b.frame.id || a.frame.flags != b.frame.flags ||
      a.frame.length != b.frame.length) {
    return false;
  }
  if (a.frame.flags & can::kRemote) return true;  // a remote request carries no data
  return std::memcmp(a.frame.data, b.frame.data, a.frame.length) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = stickslip::fuzz::input_as_file(data, size);
  std::vector<LoggedFrame> frames;
  try {
    frames = stickslip::host::read_candump_log(path);
  } catch (const stickslip::host::HostError&) {
    return 0;  // a refused log: the message is the product here, tests/host checks its content
  }
  for (const LoggedFrame& logged : frames) {
    const can::Frame& frame = logged.frame;
    check(!logged.interface.empty() && logged.interface.size() <= 15);
    for (const char c : logged.interface) check(c > ' ' && c < 0x7F);
    check(frame.timestamp_ns == logged.time_us * 1000u);
    if (frame.flags & can::kErrorFrame) {
      check((frame.flags & (can::kRemote | can::kFd)) == 0);
    } else if (frame.flags & can::kExtendedId) {
      check(frame.id <= can::kExtendedIdMask);
    } else {
      check(frame.id <= can::kStandardIdMask);
    }
    if (frame.flags & can::kFd) {
      check(valid_fd_length(frame.length) && (frame.flags & can::kRemote) == 0);
    } else {
      check(frame.length <= can::kClassicMaxLength);
    }
  }
  stickslip::host::write_candump_log(round_trip_path(), frames);
  const std::vector<LoggedFrame> back = stickslip::host::read_candump_log(round_trip_path());
  check(back.size() == frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) check(same_frame(frames[i], back[i]));
  return 0;
}
