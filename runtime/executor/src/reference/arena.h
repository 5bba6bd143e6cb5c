#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error "arena.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// The reference executor's activation memory: one allocation holding every activation tensor
// at a 16-byte-aligned offset. No buffer is shared between tensors (no liveness reuse), so
// every activation stays readable after invoke() — the oracle role needs that more than memory.

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"

namespace tlvlink::reference {

inline constexpr size_t kArenaAlignment = 16;

class Arena {
 public:
  // Lays out every non-constant tensor of `graph` and allocates the arena, zero-filled.
  // Error kOutOfMemory if the total overflows or the allocation fails.
  static Result<Arena> create(const Graph& graph);

  // The tensor's slot; empty for constants.
  std::span<std::byte> slot(int32_t tensor) const { return slots_[static_cast<size_t>(tensor)]; }
  size_t bytes() const { return bytes_; }

 private:
  struct Free {
    void operator()(std::byte* p) const;
  };
  std::unique_ptr<std::byte, Free> memory_;
  size_t bytes_ = 0;
  std::vector<std::span<std::byte>> slots_;
};

}  // namespace tlvlink::reference
