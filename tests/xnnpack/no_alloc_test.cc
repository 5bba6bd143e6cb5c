// Steady-state invoke() must not touch the heap (STYLE.md: setup allocates, the frame loop does
// not). This binary replaces the global operator new and, on glibc, interposes malloc & co.
// (what XNNPACK and pthreadpool, C libraries, would call), counting calls while invoking.
// Sanitizers own the allocator, so under ASan/TSan/MSan the test is skipped and says so.
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "xnnpack/graphs.h"
#include "xnnpack/harness.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<size_t> g_allocations{0};
}  // namespace

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define TLV_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TLV_SANITIZED 1
#endif
#if !defined(TLV_SANITIZED)
#define TLV_COUNTING 1
#if defined(__GLIBC__)
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
static void count_allocation() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
}
void* malloc(size_t n) {
  count_allocation();
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t m) {
  count_allocation();
  return __libc_calloc(n, m);
}
void* realloc(void* p, size_t n) {
  count_allocation();
  return __libc_realloc(p, n);
}
void* memalign(size_t a, size_t n) {
  count_allocation();
  return __libc_memalign(a, n);
}
void* aligned_alloc(size_t a, size_t n) {
  count_allocation();
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, size_t a, size_t n) {
  count_allocation();
  void* p = __libc_memalign(a, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
}  // extern "C"
#define TLV_COUNT_MALLOC 1
#else
#define TLV_COUNT_MALLOC 0
#endif

// The replacements pair operator new with malloc and operator delete with free. Defined in this
// file, g++ 12 at -O1/-Og inlines the delete into GoogleTest's `new TestClass` and reports free()
// on a pointer from operator new (-Wmismatched-new-delete): it does not see that both are replaced.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(size_t size) {
  if (!TLV_COUNT_MALLOC && g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  std::abort();  // tests only; the runtime itself never relies on operator new throwing
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
#else
#define TLV_COUNTING 0
#define TLV_COUNT_MALLOC 0
#endif  // !TLV_SANITIZED

namespace tlvlink::testing {
namespace {

// Invokes `frames` times after one warm-up run and returns the number of operator new calls.
size_t allocations_during_invoke(const Model& model, int threads, int frames) {
  ExecutorOptions options;
  options.threads = threads;
  auto exec = make_xnnpack_executor(model, options);
  EXPECT_TRUE(exec.ok()) << exec.error().message();
  if (!exec.ok()) return 0;
  EXPECT_TRUE((*exec)->invoke().ok());  // warm-up
  g_allocations = 0;
  g_counting = true;
  bool ok = true;
  for (int i = 0; i < frames; ++i) ok &= (*exec)->invoke().ok();
  g_counting = false;
  EXPECT_TRUE(ok);
  return g_allocations.load();
}

TEST(XnnpackNoAllocation, SteadyStateInvokeDoesNotAllocate) {
  if (!TLV_COUNTING)
    GTEST_SKIP() << "allocation counting is off under sanitizers (they own the allocator)";
  std::printf("[ counting ] operator new%s\n",
              TLV_COUNT_MALLOC ? " and malloc/calloc/realloc/memalign" : "");
  Rng rng(test_seed());
  const TGraph graph = random_chain(rng);
  auto fp32 = load_model(build_fp32(graph));
  ASSERT_NE(fp32, nullptr);
  std::vector<std::vector<float>> inputs = {
      rng.floats(fp32->graph().tensor(fp32->graph().inputs[0]).shape.elements(), -1.0f, 1.0f)};
  auto int8 = load_model(build_int8(graph, calibrate(graph, *fp32, inputs, rng)));
  ASSERT_NE(int8, nullptr);
  for (const Model* model : {fp32.get(), int8.get()}) {
    for (int threads : {1, 2}) {
      EXPECT_EQ(allocations_during_invoke(*model, threads, 20), 0u) << "threads " << threads;
    }
  }
}

}  // namespace
}  // namespace tlvlink::testing
