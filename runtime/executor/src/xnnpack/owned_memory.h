#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error \
    "owned_memory.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// Memory the XNNPACK executor owns for as long as its runtime lives: external input/output
// buffers, transposed depthwise weights, per-channel scale arrays, padded copies of constants.
// XNNPACK keeps raw pointers to all of these, so every block keeps its address until the store
// is destroyed. Allocation happens at creation only.

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "xnnpack/xnn_api.h"

namespace tlvlink::xnn {

class OwnedMemory {
 public:
  static constexpr size_t kAlignment = 64;  // cache line; XNNPACK wants >= 16

  // Zero-filled block of `bytes` usable bytes plus kExtraBytes of slack that XNNPACK kernels
  // may read past the end.
  Result<std::span<std::byte>> allocate(size_t bytes) {
    const size_t padded = (bytes + kExtraBytes + kAlignment - 1) / kAlignment * kAlignment;
    void* p = std::aligned_alloc(kAlignment, padded);
    TLV_ENSURE(p != nullptr, ErrorCode::kOutOfMemory, "cannot allocate %zu bytes", padded);
    std::memset(p, 0, padded);
    blocks_.emplace_back(static_cast<std::byte*>(p));
    return std::span<std::byte>(blocks_.back().get(), bytes);
  }

  template <typename T>
  Result<std::span<T>> allocate_array(size_t count) {
    TLV_ASSIGN_OR_RETURN(std::span<std::byte> raw, allocate(count * sizeof(T)));
    return std::span<T>(reinterpret_cast<T*>(raw.data()), count);
  }

 private:
  struct Free {
    void operator()(std::byte* p) const { std::free(p); }
  };
  std::vector<std::unique_ptr<std::byte[], Free>> blocks_;
};

}  // namespace tlvlink::xnn
