// Output files that appear under their final name only when complete: written to a temporary
// file in the same directory (same file system, so the final rename is atomic) and renamed by
// commit(). A failure - or an exception unwinding past the object - removes the temporary, so a
// failed command never leaves a half-written OUT.csv behind. Every live temporary is also
// listed in a fixed table that a signal handler can read (remove_live_temporaries), so that
// SIGINT/SIGTERM, which skip the destructors, leave none behind either.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "stickslip/host/io/number_format.hpp"

namespace stickslip::host {

class AtomicOutputFile {
 public:
  // Creates the temporary file; throws HostError naming `path` if that is impossible.
  explicit AtomicOutputFile(std::string path);
  ~AtomicOutputFile();
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  void write(const char* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  // Flushes, closes and renames to the final path; throws HostError on any failure.
  void commit();
  // Removes the temporary file now (also done by the destructor when not committed).
  void discard() noexcept;
  const std::string& path() const noexcept { return path_; }

 private:
  [[noreturn]] void fail(const char* what, int error_number);

  std::string path_;
  std::string temp_path_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int slot_ = -1;  // index in the table of live temporaries; -1 when not listed
};

// Commits `output`, then `stats` (if any); when the second commit fails the first file is
// removed again, so that a run leaves both files or neither.
void commit_with_stats(AtomicOutputFile& output, AtomicOutputFile* stats);

// Unlinks every temporary an AtomicOutputFile holds now. Async-signal-safe (unlink(2) only, over
// a table of fixed size written before the path is published), for a SIGINT/SIGTERM handler;
// returns how many it removed. Final outputs are never touched: a rename has either happened
// or not, so an existing OUT.csv stays as it was.
int remove_live_temporaries() noexcept;

// Row-oriented CSV output into a large buffer, handed to the file in big blocks.
class CsvWriter {
 public:
  explicit CsvWriter(AtomicOutputFile& file, std::size_t block_bytes = std::size_t{1} << 22);
  ~CsvWriter() = default;
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  void text(std::string_view text);
  // Full precision, "%.17g": reads back to the same double.
  void number(double value) {
    reserve(kMaxG17Chars);
    end_ = format_g17(value, end_);
  }
  void flag(bool value) {
    reserve(1);
    *end_++ = value ? '1' : '0';
  }
  void separator() {
    reserve(1);
    *end_++ = ',';
  }
  void end_row() {
    reserve(1);
    *end_++ = '\n';
    if (static_cast<std::size_t>(end_ - buffer_.data()) >= block_bytes_) flush();
  }
  // Hands everything buffered to the file (the caller then commits the file).
  void flush();

 private:
  void reserve(std::size_t bytes) {
    if (static_cast<std::size_t>(end_ - buffer_.data()) + bytes > buffer_.size()) grow(bytes);
  }
  void grow(std::size_t bytes);

  AtomicOutputFile& file_;
  std::size_t block_bytes_;
  std::vector<char> buffer_;
  char* end_;
};

}  // namespace stickslip::host
