// Vector BLF (binary logging format). No official description is published; the layout here is
// the one python-can's blf.py and Toby Lorenz' vector_blf library read and write:
//
//   file header   "LOGG", u32 header size, ... (the objects start at header size)
//   object        "LOBJ", u16 header size, u16 header version, u32 object size, u32 type,
//                 then (version 1) u32 flags, u16 client, u16 object version, u64 timestamp
//                 or (version 2) u32 flags, u8 status, pad, u16 object version, u64 timestamp,
//                 u64 original timestamp; then the body; objects start on 4-byte boundaries
//   LOG_CONTAINER (type 10)  u16 method (0 stored, 2 zlib), 6 pad, u32 uncompressed size,
//                 4 pad, then the data: a stream of objects that may continue in the next
//                 container
//   CAN_MESSAGE (1), CAN_MESSAGE2 (86)  u16 channel, u8 flags (bit 0 Tx, bit 7 remote),
//                 u8 dlc, u32 id (bit 31: extended), 8 data bytes
//
// The file header's start time is a SYSTEMTIME at byte 40 (u16 year, month, day of week, day,
// hour, minute, second, millisecond); it is kept as CanLog::start_time_epoch_s, not added.
//
// The object flags give the timestamp unit: 1 -> 10 us, 2 -> 1 ns. Every other object type
// (CAN FD, error frames, statistics, markers) is counted and skipped. All integers are
// little-endian. Every length is checked against what is there before it is used, and a
// container may inflate to at most 64 MiB, so a hostile file costs no more than that.
#include <zlib.h>

#include <cstring>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/can_log.hpp"

namespace stickslip::host {
namespace {

constexpr std::uint32_t kCanMessage = 1;
constexpr std::uint32_t kLogContainer = 10;
constexpr std::uint32_t kCanMessage2 = 86;
constexpr std::size_t kBaseHeader = 16;
constexpr std::size_t kFileHeaderMin = 144;
constexpr std::uint32_t kMaxContainerBytes = 64u << 20;

std::uint16_t u16(const unsigned char* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
std::uint64_t u64(const unsigned char* p) {
  return static_cast<std::uint64_t>(u32(p)) | (static_cast<std::uint64_t>(u32(p + 4)) << 32);
}

// The header's start time in seconds since the epoch, or 0 when it is no date (a writer that
// leaves it zero): only its size matters to the reader (CanLog::start_time_epoch_s).
double start_time_epoch_s(const unsigned char* header) {
  constexpr std::size_t kStartTime = 40;
  const unsigned char* p = header + kStartTime;
  const int year = u16(p), month = u16(p + 2), day = u16(p + 6);
  if (year < 1970 || year > 9999 || month < 1 || month > 12 || day < 1 || day > 31) return 0.0;
  // Days from 1970-01-01 to the date (the civil-calendar count of H. Hinnant's days_from_civil).
  const int y = year - (month <= 2 ? 1 : 0);
  const int era = y / 400;
  const int year_of_era = y - era * 400;
  const int day_of_year = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  const double days = static_cast<double>(era) * 146097.0 + day_of_era - 719468.0;
  return days * 86400.0 + u16(p + 8) * 3600.0 + u16(p + 10) * 60.0 + u16(p + 12) +
         u16(p + 14) * 1e-3;
}

class BlfParser {
 public:
  BlfParser(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  CanLog parse() {
    log_.format = CanLogFormat::kBlf;
    const auto* data = reinterpret_cast<const unsigned char*>(bytes_.data());
    if (bytes_.size() < kFileHeaderMin || std::memcmp(data, "LOGG", 4) != 0)
      fail_at(0, "not a BLF file (a 144-byte header starting 'LOGG' expected)");
    const std::uint32_t header_size = u32(data + 4);
    if (header_size < kFileHeaderMin || header_size > bytes_.size())
      fail_at(4, "file header size " + std::to_string(header_size) + " is not 144.." +
                     std::to_string(bytes_.size()));
    log_.start_time_epoch_s = start_time_epoch_s(data);
    std::size_t at = header_size;
    while (at < bytes_.size()) {
      // Top-level objects are 4-byte aligned; trailing padding bytes end the file.
      if (bytes_.size() - at < kBaseHeader) {
        bool zeros = true;
        for (std::size_t i = at; i < bytes_.size(); ++i) zeros = zeros && data[i] == 0;
        if (zeros) break;
        fail_at(at, "truncated object header (" + std::to_string(bytes_.size() - at) + " bytes)");
      }
      if (std::memcmp(data + at, "LOBJ", 4) != 0) fail_at(at, "expected an object ('LOBJ')");
      const std::uint32_t size = u32(data + at + 8);
      const std::uint32_t type = u32(data + at + 12);
      if (size < kBaseHeader || size > bytes_.size() - at)
        fail_at(at, "object size " + std::to_string(size) + " runs beyond the file (" +
                        std::to_string(bytes_.size() - at) + " bytes left)");
      if (type == kLogContainer) {
        container(data + at, size, at);
      } else {
        object(data + at, size, where_top(at));
      }
      at += size + size % 4;
    }
    bool padding_only = tail_.size() < 4;
    for (const unsigned char byte : tail_) padding_only = padding_only && byte == 0;
    if (!padding_only) {
      fail_at(bytes_.size(), "the last container ends inside an object (" +
                                 std::to_string(tail_.size()) + " bytes left over)");
    }
    return std::move(log_);
  }

 private:
  [[noreturn]] void fail_at(std::size_t offset, const std::string& what) const {
    throw HostError(path_ + ": byte " + std::to_string(offset) + ": " + what);
  }
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw HostError(path_ + ": " + where + ": " + what);
  }
  std::string where_top(std::size_t offset) const {
    return "object at byte " + std::to_string(offset);
  }

  void container(const unsigned char* object_data, std::uint32_t size, std::size_t offset) {
    constexpr std::size_t kContainerHeader = kBaseHeader + 16;
    if (size < kContainerHeader) fail_at(offset, "log container shorter than its header");
    const std::uint16_t method = u16(object_data + kBaseHeader);
    const std::uint32_t uncompressed = u32(object_data + kBaseHeader + 8);
    const unsigned char* body = object_data + kContainerHeader;
    const std::size_t body_size = size - kContainerHeader;
    std::vector<unsigned char> inflated;
    if (method == 0) {
      inflated.assign(body, body + body_size);
    } else if (method == 2) {
      if (uncompressed > kMaxContainerBytes)
        fail_at(offset, "log container claims " + std::to_string(uncompressed) +
                            " uncompressed bytes (at most 64 MiB are read)");
      // Deflate expands at most 1032:1: a larger claim is refused before anything is allocated.
      constexpr std::uint64_t kMaxDeflateRatio = 1032;
      if (uncompressed > kMaxDeflateRatio * body_size + 64)
        fail_at(offset, "log container claims " + std::to_string(uncompressed) +
                            " uncompressed bytes from " + std::to_string(body_size) +
                            " compressed ones (more than zlib can inflate)");
      inflated.resize(uncompressed);
      uLongf got = uncompressed;
      const int status = uncompress(inflated.data(), &got, body, static_cast<uLong>(body_size));
      if (status != Z_OK || got != uncompressed)
        fail_at(offset, std::string("log container does not inflate to its ") +
                            std::to_string(uncompressed) +
                            " bytes (zlib: " + (status == Z_OK ? "short" : zError(status)) + ")");
    } else {
      fail_at(offset, "log container compression method " + std::to_string(method) +
                          " (0 stored and 2 zlib are known)");
    }
    // Objects may continue from the previous container.
    tail_.insert(tail_.end(), inflated.begin(), inflated.end());
    std::size_t at = 0;
    const std::string where = "log container at byte " + std::to_string(offset);
    for (;;) {
      // An object is followed by (its size mod 4) zero bytes of padding.
      std::size_t padding = 0;
      while (tail_.size() - at >= 4 && std::memcmp(&tail_[at], "LOBJ", 4) != 0) {
        if (tail_[at] != 0 || ++padding > 3) {
          fail(where, "expected an object ('LOBJ') at byte " + std::to_string(at) + " of its data");
        }
        ++at;
      }
      if (tail_.size() - at < kBaseHeader) break;
      const std::uint32_t object_size = u32(&tail_[at + 8]);
      if (object_size < kBaseHeader)
        fail(where, "object size " + std::to_string(object_size) + " at byte " +
                        std::to_string(at) + " of its data");
      if (object_size > tail_.size() - at) break;  // continues in the next container
      object(&tail_[at], object_size, where + ", object at byte " + std::to_string(at));
      at += object_size;
    }
    tail_.erase(tail_.begin(), tail_.begin() + static_cast<std::ptrdiff_t>(at));
    if (tail_.size() > kMaxContainerBytes)
      fail(where, "an object longer than 64 MiB spans containers");
  }

  void object(const unsigned char* p, std::uint32_t size, const std::string& where) {
    const std::uint16_t header_size = u16(p + 4);
    const std::uint16_t version = u16(p + 6);
    const std::uint32_t type = u32(p + 12);
    if (type != kCanMessage && type != kCanMessage2) {
      ++log_.skipped_events;
      return;
    }
    std::size_t header = 0;
    if (version == 1) {
      header = kBaseHeader + 16;
    } else if (version == 2) {
      header = kBaseHeader + 24;
    } else {
      fail(where, "object header version " + std::to_string(version) + " (1 or 2 are known)");
    }
    if (header_size != header)
      fail(where, "object header size " + std::to_string(header_size) + " for version " +
                      std::to_string(version) + " (expected " + std::to_string(header) + ")");
    constexpr std::size_t kCanBody = 16;
    if (size < header + kCanBody)
      fail(where, "CAN message object of " + std::to_string(size) + " bytes (at least " +
                      std::to_string(header + kCanBody) + " expected)");
    const std::uint32_t flags = u32(p + kBaseHeader);
    const std::uint64_t stamp = u64(p + kBaseHeader + (version == 1 ? 8 : 8));
    if (flags != 1 && flags != 2)
      fail(where, "timestamp unit flags " + std::to_string(flags) + " (1: 10 us, 2: 1 ns)");
    const unsigned char* body = p + header;
    LogFrame frame;
    frame.time_s = static_cast<double>(stamp) / (flags == 1 ? 1e5 : 1e9);
    frame.channel = std::to_string(u16(body));
    const std::uint8_t message_flags = body[2];
    if ((message_flags & 0x80u) != 0) {  // remote request
      ++log_.skipped_events;
      return;
    }
    frame.direction = (message_flags & 0x01u) != 0 ? 'T' : 'R';
    frame.dlc = body[3];
    if (frame.dlc > 15) fail(where, "DLC " + std::to_string(frame.dlc) + " (0..15 expected)");
    const std::uint32_t id = u32(body + 4);
    frame.extended = (id & 0x80000000u) != 0;
    frame.id = id & 0x7FFFFFFFu;
    if (frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu))
      fail(where, "CAN id " + std::to_string(frame.id) + " beyond its width");
    frame.length = static_cast<std::uint8_t>(frame.dlc < 8 ? frame.dlc : 8);
    std::memcpy(frame.data.data(), body + 8, frame.length);
    log_.frames.push_back(std::move(frame));
  }

  std::string_view bytes_;
  const std::string& path_;
  CanLog log_;
  std::vector<unsigned char> tail_;
};

}  // namespace

CanLog parse_blf(std::string_view bytes, const std::string& path) {
  return BlfParser(bytes, path).parse();
}

}  // namespace stickslip::host
