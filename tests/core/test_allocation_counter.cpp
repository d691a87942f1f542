#include <cstdlib>

#include "CppUTest/TestHarness.h"
#include "support/allocation_counter.hpp"

// The no-allocation proofs are only as good as the counter: it must see a real allocation.
TEST_GROUP(AllocationCounter){};

namespace {
// The optimiser may drop an allocation whose pointer goes nowhere; this one escapes.
void* volatile escaped_pointer = nullptr;
}  // namespace

TEST(AllocationCounter, SeesMallocAndOperatorNew) {
  stickslip::test::start_counting_allocations();
  void* block = std::malloc(64);
  escaped_pointer = block;
  int* value = new int(3);
  escaped_pointer = value;
  const auto seen = stickslip::test::stop_counting_allocations();
  delete value;
  std::free(block);
  CHECK_TRUE(seen.calls >= 2);
}

TEST(AllocationCounter, CountsNothingWhenNothingAllocates) {
  stickslip::test::start_counting_allocations();
  volatile int sum = 0;
  for (int i = 0; i < 100; ++i) sum = sum + i;
  const auto seen = stickslip::test::stop_counting_allocations();
  UNSIGNED_LONGS_EQUAL(0, seen.calls);
  LONGS_EQUAL(4950, sum);
}
