// Counts the heap allocations of the test binary that includes this header
// (include it in one translation unit of a binary: it defines the process's
// allocation functions). The no-allocation tests read
// testing_support::allocations() before and after the steps they check.
//
// What is counted:
// - in a normal build, every call of malloc, calloc and realloc, whoever makes
//   it: C++'s operator new (libstdc++'s calls malloc), Eigen's dense and
//   sparse storage (std::malloc, also from inside libmsd), OpenMP's runtime.
//   The replacements forward to glibc's allocator (__libc_malloc and its
//   kin), so glibc's own free() releases what they return;
// - under AddressSanitizer, which owns malloc, only C++'s operator new: Eigen's
//   std::malloc is not seen there, so the normal build's run of the same
//   tests is the one that covers it.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace testing_support {

inline std::atomic<long> g_allocation_count{0};

// Allocations so far in this process.
inline long allocations() { return g_allocation_count.load(); }

}  // namespace testing_support

#if defined(__SANITIZE_ADDRESS__)

__attribute__((noinline)) void* operator new(std::size_t n) {
  ++testing_support::g_allocation_count;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// New and delete out of line: inlined into their callers (gtest's CreateTest,
// a unique_ptr's destructor), gcc sees malloc paired with a sized delete or
// free() on a pointer from operator new and warns -Wmismatched-new-delete.
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }

#else

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t n) {
  ++testing_support::g_allocation_count;
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t n) {
  ++testing_support::g_allocation_count;
  return __libc_calloc(count, n);
}
void* realloc(void* p, std::size_t n) {
  ++testing_support::g_allocation_count;
  return __libc_realloc(p, n);
}
}

#endif
