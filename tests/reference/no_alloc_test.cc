// invoke() must not allocate (STYLE.md: setup allocates, the frame loop does not). This binary
// replaces the global operator new family and counts calls while a flag is set. The reference
// executor's own code calls nothing else that allocates (no malloc in kernels).
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>

#include "reference/all_ops_models.h"
#include "reference/ref_util.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<size_t> g_allocations{0};

void* counted_alloc(size_t n, size_t alignment = 0) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (n == 0) n = 1;
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (n + alignment - 1) / alignment * alignment)
                : std::malloc(n);
  return p;
}
}  // namespace

void* operator new(size_t n) {
  void* p = counted_alloc(n);
  if (p == nullptr) std::abort();
  return p;
}
void* operator new[](size_t n) {
  return operator new(n);
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  return counted_alloc(n);
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  return counted_alloc(n);
}
void* operator new(size_t n, std::align_val_t a) {
  void* p = counted_alloc(n, static_cast<size_t>(a));
  if (p == nullptr) std::abort();
  return p;
}
void* operator new[](size_t n, std::align_val_t a) {
  return operator new(n, a);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, size_t, std::align_val_t) noexcept {
  std::free(p);
}

namespace tlvlink::reference_test {
namespace {

size_t allocations_during_invokes(bool int8, int runs) {
  auto model = testing::load_model(all_ops_model(int8));
  EXPECT_NE(model, nullptr);
  if (model == nullptr) return 0;
  auto exec = make_reference_executor(*model);
  EXPECT_TRUE(exec.ok()) << exec.error().message();
  if (!exec.ok()) return 0;
  std::vector<float> x(kAllOpsInputElements, 0.25f);
  std::memcpy((*exec)->input(0).data(), x.data(), (*exec)->input(0).size());
  g_allocations = 0;
  g_counting = true;
  bool all_ok = true;
  for (int i = 0; i < runs; ++i) all_ok = (*exec)->invoke().ok() && all_ok;
  // A failing invoke builds an Error in a fixed buffer, also without allocating.
  std::memcpy((*exec)->input(0).data(), "\xff\xff\xff\x7f", 4);  // NaN
  const bool rejected = !(*exec)->invoke().ok();
  g_counting = false;
  EXPECT_TRUE(all_ok);
  EXPECT_TRUE(rejected);
  return g_allocations.load();
}

TEST(ReferenceNoAlloc, CounterSeesAllocations) {
  g_allocations = 0;
  g_counting = true;
  void* p = ::operator new(64);  // a direct call cannot be elided by the compiler
  g_counting = false;
  ::operator delete(p);
  EXPECT_EQ(g_allocations.load(), 1u);
}

TEST(ReferenceNoAlloc, InvokeDoesNotAllocateFloat32) {
  EXPECT_EQ(allocations_during_invokes(false, 5), 0u);
}

TEST(ReferenceNoAlloc, InvokeDoesNotAllocateInt8) {
  EXPECT_EQ(allocations_during_invokes(true, 5), 0u);
}

}  // namespace
}  // namespace tlvlink::reference_test
