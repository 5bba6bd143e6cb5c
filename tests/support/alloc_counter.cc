// Replacements of the global operator new family that count calls while counting is on.

#include "support/alloc_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<bool> g_counting{false};
std::atomic<size_t> g_allocations{0};

void* counted_alloc(size_t n, size_t alignment = 0) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (n == 0) n = 1;
  return alignment > alignof(std::max_align_t)
             ? std::aligned_alloc(alignment, (n + alignment - 1) / alignment * alignment)
             : std::malloc(n);
}

}  // namespace

namespace tlvlink::testing {

void start_counting_allocations() {
  g_allocations = 0;
  g_counting = true;
}

size_t stop_counting_allocations() {
  g_counting = false;
  return g_allocations.load();
}

}  // namespace tlvlink::testing

void* operator new(size_t n) {
  void* p = counted_alloc(n);
  if (p == nullptr) std::abort();
  return p;
}
void* operator new[](size_t n) { return operator new(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new[](size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new(size_t n, std::align_val_t a) {
  void* p = counted_alloc(n, static_cast<size_t>(a));
  if (p == nullptr) std::abort();
  return p;
}
void* operator new[](size_t n, std::align_val_t a) { return operator new(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { std::free(p); }
