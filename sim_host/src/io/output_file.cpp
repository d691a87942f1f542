#include "stickslip/host/io/output_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

// The live temporaries, readable from a signal handler: no heap, the state published only after
// the path is complete (a handler sees a slot as free, being written, or holding a whole path).
// More live temporaries than slots than this are not listed (simulate writes two, sweep one).
constexpr int kTemporarySlots = 32;
constexpr std::size_t kTemporaryPathBytes = 4096;
enum SlotState : int { kFree = 0, kClaimed = 1, kLive = 2 };
std::atomic<int> slot_state[kTemporarySlots];
char slot_path[kTemporarySlots][kTemporaryPathBytes];

int list_temporary(const std::string& path) noexcept {
  if (path.size() >= kTemporaryPathBytes) return -1;
  for (int i = 0; i < kTemporarySlots; ++i) {
    int expected = kFree;
    if (!slot_state[i].compare_exchange_strong(expected, kClaimed)) continue;
    std::memcpy(slot_path[i], path.c_str(), path.size() + 1);
    slot_state[i].store(kLive);
    return i;
  }
  return -1;
}

void unlist_temporary(int& slot) noexcept {
  if (slot >= 0) slot_state[slot].store(kFree);
  slot = -1;
}

}  // namespace

int remove_live_temporaries() noexcept {
  int removed = 0;
  for (int i = 0; i < kTemporarySlots; ++i) {
    if (slot_state[i].load() == kLive && ::unlink(slot_path[i]) == 0) ++removed;
  }
  return removed;
}

AtomicOutputFile::AtomicOutputFile(std::string path) : path_(std::move(path)) {
  if (path_.empty()) throw UsageError("output file name is empty");
  const std::filesystem::path final_path(path_);
  std::error_code ignored;
  if (std::filesystem::is_directory(final_path, ignored)) {
    throw HostError(path_ + ": cannot write the output: it is a directory");
  }
  // A hidden name next to the final file; "x" (exclusive) never reuses someone else's file.
  const std::string prefix =
      (final_path.parent_path() / ("." + final_path.filename().string() + ".tmp")).string();
  // Listed before it is created: a signal between the two would otherwise leave it behind. A
  // file that already has the name carries this process's id, so it is a dead process's leftover.
  for (unsigned attempt = 0; attempt < 1000 && file_ == nullptr; ++attempt) {
    temp_path_ = prefix + std::to_string(::getpid()) + "-" + std::to_string(attempt);
    slot_ = list_temporary(temp_path_);
    file_ = std::fopen(temp_path_.c_str(), "wbx");
    if (file_ != nullptr) break;
    const int error_number = errno;
    unlist_temporary(slot_);
    errno = error_number;
    if (error_number != EEXIST) break;
  }
  if (file_ == nullptr) {
    const int error_number = errno;
    temp_path_.clear();
    throw HostError(path_ + ": cannot create the output file: " + std::strerror(error_number));
  }
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!committed_) discard();
}

void AtomicOutputFile::discard() noexcept {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temp_path_.empty()) {
    std::remove(temp_path_.c_str());
    temp_path_.clear();
  }
  unlist_temporary(slot_);
}

void AtomicOutputFile::fail(const char* what, int error_number) {
  discard();
  throw HostError(path_ + ": " + what + ": " + std::strerror(error_number));
}

void AtomicOutputFile::write(const char* data, std::size_t size) {
  if (file_ == nullptr) throw HostError(path_ + ": write after the file was closed");
  if (size != 0 && std::fwrite(data, 1, size, file_) != size) fail("write failed", errno);
}

void AtomicOutputFile::commit() {
  if (file_ == nullptr) throw HostError(path_ + ": commit after the file was closed");
  if (std::fflush(file_) != 0) fail("write failed", errno);
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) fail("write failed", errno);
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) fail("cannot rename into place", errno);
  unlist_temporary(slot_);
  temp_path_.clear();
  committed_ = true;
}

CsvWriter::CsvWriter(AtomicOutputFile& file, std::size_t block_bytes)
    : file_(file), block_bytes_(block_bytes), buffer_(block_bytes + 4096), end_(buffer_.data()) {}

void CsvWriter::text(std::string_view text) {
  reserve(text.size());
  std::memcpy(end_, text.data(), text.size());
  end_ += text.size();
}

void CsvWriter::flush() {
  file_.write(buffer_.data(), static_cast<std::size_t>(end_ - buffer_.data()));
  end_ = buffer_.data();
}

void CsvWriter::grow(std::size_t bytes) {
  const std::size_t used = static_cast<std::size_t>(end_ - buffer_.data());
  buffer_.resize(used + bytes + buffer_.size());
  end_ = buffer_.data() + used;
}

void commit_with_stats(AtomicOutputFile& output, AtomicOutputFile* stats) {
  output.commit();
  if (stats == nullptr) return;
  try {
    stats->commit();
  } catch (...) {
    std::remove(output.path().c_str());
    throw;
  }
}

}  // namespace stickslip::host
