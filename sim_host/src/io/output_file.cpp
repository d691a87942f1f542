#include "stickslip/host/io/output_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

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
  for (unsigned attempt = 0; attempt < 1000 && file_ == nullptr; ++attempt) {
    temp_path_ = prefix + std::to_string(::getpid()) + "-" + std::to_string(attempt);
    file_ = std::fopen(temp_path_.c_str(), "wbx");
    if (file_ == nullptr && errno != EEXIST) break;
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

}  // namespace stickslip::host
