// CAN bus logs as loggers and vehicle tools write them: can-utils candump (-l), Vector ASC and
// BLF, PEAK TRC (1.x and 2.x). Every reader returns the classic CAN data frames in file order
// and counts what it read over (remote, error and CAN FD frames, status and other events). The
// format is told from the content (docs/RECORDINGS.md); a bad file is one HostError naming the
// file and the line (text) or byte offset of the object (BLF).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace stickslip::host {

enum class CanLogFormat { kCandump, kAsc, kBlf, kTrc };

const char* format_name(CanLogFormat format) noexcept;

struct LogFrame {
  // Seconds as the log writes them: candump since the epoch, ASC and TRC since the start of the
  // measurement, BLF since the file's start time (its object timestamps).
  double time_s = 0.0;
  std::string channel;  // "can0", "1", ...
  std::uint32_t id = 0;
  bool extended = false;
  std::uint8_t dlc = 0;     // as logged (0..15; a classic frame carries min(dlc, 8) bytes)
  std::uint8_t length = 0;  // data bytes in `data`
  std::array<std::uint8_t, 8> data{};
  char direction = 0;    // 'R' received, 'T' transmitted, 0 when the log does not say
  std::size_t line = 0;  // text logs: the frame's line in the file (1-based); BLF: 0
};

struct CanLog {
  CanLogFormat format = CanLogFormat::kCandump;
  std::vector<LogFrame> frames;
  std::size_t skipped_events = 0;  // lines or objects that are not classic data frames
  // The wall-clock time of t = 0 in seconds since the epoch where the log's header records it
  // (BLF's start time), else 0. Not added to the times; it tells how large the clock was whose
  // readings a writer subtracted (python-can's BLFWriter), which bounds their rounding.
  double start_time_epoch_s = 0.0;
};

// The channels (LogFrame::channel) that carry data frames, sorted, each once.
std::vector<std::string> log_channels(const CanLog& log);

// The format of the file at `path`, from its first bytes and lines; the extension (.log, .asc,
// .blf, .trc) decides only when the content does not. Throws HostError when neither does.
CanLogFormat detect_can_log_format(const std::string& path);
CanLogFormat detect_can_log_format(std::string_view head, const std::string& path);

// Detects the format and reads the log.
CanLog read_can_log(const std::string& path);

// One format each, on the bytes of a file named `path` (in messages).
CanLog parse_candump_text(std::string_view bytes, const std::string& path);
CanLog parse_asc(std::string_view bytes, const std::string& path);
CanLog parse_blf(std::string_view bytes, const std::string& path);
CanLog parse_trc(std::string_view bytes, const std::string& path);

}  // namespace stickslip::host
