#include "support/allocation_counter.hpp"

#include <atomic>
#include <cstddef>

// Two ways to see every allocation of the test binary:
// - normal builds replace malloc and friends and forward to glibc's real allocator, exported
//   under the __libc_* names for exactly this kind of interposition;
// - under AddressSanitizer, malloc belongs to the sanitizer runtime (replacing it would hand
//   glibc blocks to ASan's free), so the counter installs the sanitizer's own allocation hook
//   instead, which sees malloc, calloc, realloc, the aligned forms and operator new alike.
#if defined(__SANITIZE_ADDRESS__)
#define STICKSLIP_COUNT_WITH_SANITIZER_HOOK 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STICKSLIP_COUNT_WITH_SANITIZER_HOOK 1
#endif
#endif

#if defined(STICKSLIP_COUNT_WITH_SANITIZER_HOOK)
// Declared here as in LLVM's <sanitizer/allocator_interface.h>, which GCC does not install; both
// runtimes (libasan and compiler-rt) export it.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                             std::size_t),
                                                         void (*free_hook)(const volatile void*));
#endif

namespace {
std::atomic<bool> armed{false};
std::atomic<std::size_t> calls{0};
void note() noexcept {
  if (armed.load(std::memory_order_relaxed)) calls.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

#if defined(STICKSLIP_COUNT_WITH_SANITIZER_HOOK)

namespace {
void on_malloc(const volatile void* /*pointer*/, std::size_t /*size*/) {
  note();
}
void on_free(const volatile void* /*pointer*/) {}
// Installed before main() runs (a static initialiser); the runtime keeps a handful of hook slots.
const int hook_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}  // namespace

#else

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* pointer);
}

extern "C" {
void* malloc(std::size_t size) {
  note();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  note();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) {
  note();
  return __libc_realloc(pointer, size);
}
void* memalign(std::size_t alignment, std::size_t size) {
  note();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  note();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  note();
  *out = __libc_memalign(alignment, size);
  return *out == nullptr ? 12 /* ENOMEM */ : 0;
}
void free(void* pointer) {
  __libc_free(pointer);
}
}

#endif

namespace stickslip::test {

void start_counting_allocations() noexcept {
  calls.store(0);
#if defined(STICKSLIP_COUNT_WITH_SANITIZER_HOOK)
  // A hook that failed to install counts nothing, and AllocationCounter.SeesMallocAndOperatorNew
  // then fails: the no-allocation proofs cannot pass vacuously.
  if (hook_installed == 0) return;
#endif
  armed.store(true);
}

AllocationCount stop_counting_allocations() noexcept {
  armed.store(false);
  return AllocationCount{calls.load()};
}

}  // namespace stickslip::test
