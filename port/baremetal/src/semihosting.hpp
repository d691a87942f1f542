// Arm semihosting on QEMU's mps2 boards: files, console output and the exit status of a run
// (bkpt 0xab; r0 = operation, r1 = argument block). For the QEMU builds only: on a board without a
// debugger attached the breakpoint would halt the core.
#pragma once

#include <cstddef>
#include <cstdint>

namespace semihosting {

inline int call(int operation, const void* argument) {
  register int r0 __asm("r0") = operation;
  register const void* r1 __asm("r1") = argument;
  __asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}
constexpr int kSysOpen = 0x01, kSysWrite0 = 0x04, kSysWrite = 0x05, kSysRead = 0x06,
              kSysExit = 0x18;

inline int open_file(const char* name, int mode) {
  std::size_t length = 0;
  while (name[length] != '\0') ++length;
  const std::uintptr_t block[3] = {reinterpret_cast<std::uintptr_t>(name),
                                   static_cast<std::uintptr_t>(mode), length};
  return call(kSysOpen, block);
}
inline void print(const char* text) {
  call(kSysWrite0, text);
}
inline void print_number(std::uint64_t value) {
  char digits[24];
  int at = 23;
  digits[at] = '\0';
  do {
    digits[--at] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u);
  print(digits + at);
}
// Inlined: a call to it would be a function that never returns, which the static bound of the
// receive interrupt (tools/elf-wcet.py) cannot take; inline, its loop ends the run.
[[noreturn]] __attribute__((always_inline)) inline void exit_with(bool success) {
  // ADP_Stopped_ApplicationExit (QEMU exits 0) or ADP_Stopped_RunTimeErrorUnknown (exits 1).
  call(kSysExit, reinterpret_cast<const void*>(success ? 0x20026u : 0x20023u));
  for (;;) {
  }
}

}  // namespace semihosting
