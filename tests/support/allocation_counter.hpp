// Counts heap allocations made while armed, by replacing malloc and friends in the test binary
// (every operator new, CppUTest's and libstdc++'s, ends in malloc).
#pragma once

#include <cstddef>

namespace stickslip::test {

struct AllocationCount {
  std::size_t calls;  // malloc, calloc, realloc, aligned allocations
};

// Arms the counter and resets it to zero.
void start_counting_allocations() noexcept;
// Disarms the counter and returns what it saw since start_counting_allocations().
AllocationCount stop_counting_allocations() noexcept;

}  // namespace stickslip::test
