// invoke() must not allocate (STYLE.md: setup allocates, the frame loop does not), counted by
// support/alloc_counter. The reference executor's own code calls nothing else that allocates
// (no malloc in kernels).
#include <cstring>

#include "reference/all_ops_models.h"
#include "reference/ref_util.h"
#include "support/alloc_counter.h"

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
  testing::start_counting_allocations();
  bool all_ok = true;
  for (int i = 0; i < runs; ++i) all_ok = (*exec)->invoke().ok() && all_ok;
  // A failing invoke builds an Error in a fixed buffer, also without allocating.
  std::memcpy((*exec)->input(0).data(), "\xff\xff\xff\x7f", 4);  // NaN
  const bool rejected = !(*exec)->invoke().ok();
  const size_t allocations = testing::stop_counting_allocations();
  EXPECT_TRUE(all_ok);
  EXPECT_TRUE(rejected);
  return allocations;
}

TEST(ReferenceNoAlloc, CounterSeesAllocations) {
  testing::start_counting_allocations();
  void* p = ::operator new(64);  // a direct call cannot be elided by the compiler
  const size_t allocations = testing::stop_counting_allocations();
  ::operator delete(p);
  EXPECT_EQ(allocations, 1u);
}

TEST(ReferenceNoAlloc, InvokeDoesNotAllocateFloat32) {
  EXPECT_EQ(allocations_during_invokes(false, 5), 0u);
}

TEST(ReferenceNoAlloc, InvokeDoesNotAllocateInt8) {
  EXPECT_EQ(allocations_during_invokes(true, 5), 0u);
}

}  // namespace
}  // namespace tlvlink::reference_test
