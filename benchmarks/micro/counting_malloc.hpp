#pragma once
// Counts heap allocations (malloc, calloc, realloc, the aligned forms; operator new and Eigen
// allocate through them) of the whole process while counting is on: for "allocations per step"
// figures. Replaces glibc's allocator entry points by forwarders to its __libc_* functions, so
// include it in exactly one translation unit of an executable, and never in a sanitizer build
// (the sanitizers replace the same functions).
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <execinfo.h>
#include <unistd.h>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

namespace dc::bench {

/// Allocations since the process started, counted only between start() and stop().
class AllocationCounter {
 public:
  static void start() { on().store(true, std::memory_order_relaxed); }
  static void stop() { on().store(false, std::memory_order_relaxed); }
  [[nodiscard]] static long count() { return counter().load(std::memory_order_relaxed); }
  static void note() {
    if (on().load(std::memory_order_relaxed)) {
      counter().fetch_add(1, std::memory_order_relaxed);
      static const bool trace = std::getenv("DC_ALLOC_TRACE") != nullptr;
      thread_local bool in = false;
      if (trace && !in) {
        in = true;
        void* buf[14];
        const int n = backtrace(buf, 14);
        backtrace_symbols_fd(buf, n, 2);
        write(2, "----\n", 5);
        in = false;
      }
    }
  }

 private:
  static std::atomic<bool>& on() {
    static std::atomic<bool> flag{false};
    return flag;
  }
  static std::atomic<long>& counter() {
    static std::atomic<long> n{0};
    return n;
  }
};

}  // namespace dc::bench

extern "C" {
void* malloc(std::size_t n) {
  dc::bench::AllocationCounter::note();
  return __libc_malloc(n);
}
void* calloc(std::size_t k, std::size_t n) {
  dc::bench::AllocationCounter::note();
  return __libc_calloc(k, n);
}
void* realloc(void* p, std::size_t n) {
  dc::bench::AllocationCounter::note();
  return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
void* memalign(std::size_t a, std::size_t n) {
  dc::bench::AllocationCounter::note();
  return __libc_memalign(a, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  dc::bench::AllocationCounter::note();
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, std::size_t a, std::size_t n) {
  dc::bench::AllocationCounter::note();
  void* p = __libc_memalign(a, n);
  if (p == nullptr && n != 0) return ENOMEM;
  *out = p;
  return 0;
}
}
