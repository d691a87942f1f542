// What the file-reading fuzz targets share: the input bytes as a file the reader can open (a
// memory file reached as /proc/self/fd/N, rewritten for every input) and a check that stops the
// fuzzer with a crash report when an invariant fails.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace stickslip::fuzz {

inline void check(bool condition) {
  if (!condition) __builtin_trap();
}

// Writes data[0, size) into the target's memory file and returns its path.
inline const std::string& input_as_file(const std::uint8_t* data, std::size_t size) {
  static const int file = memfd_create("stickslip_fuzz_input", 0);
  static const std::string path = "/proc/self/fd/" + std::to_string(file);
  if (file < 0) std::abort();
  check(ftruncate(file, 0) == 0);
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = pwrite(file, data + written, size - written, static_cast<off_t>(written));
    check(n > 0);
    written += static_cast<std::size_t>(n);
  }
  return path;
}

}  // namespace stickslip::fuzz
