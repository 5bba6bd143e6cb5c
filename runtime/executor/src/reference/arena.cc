#include "reference/arena.h"

#include <cstdlib>
#include <cstring>
#include <limits>

namespace tlvlink::reference {

void Arena::Free::operator()(std::byte* p) const { std::free(p); }

Result<Arena> Arena::create(const Graph& graph) {
  constexpr size_t kMax = std::numeric_limits<size_t>::max() - kArenaAlignment;
  std::vector<size_t> offsets(graph.tensors.size(), 0);
  size_t total = 0;
  for (size_t t = 0; t < graph.tensors.size(); ++t) {
    const Tensor& tensor = graph.tensors[t];
    if (tensor.is_constant()) continue;
    const size_t bytes = tensor.bytes();
    TLV_ENSURE(bytes <= kMax - total, ErrorCode::kOutOfMemory,
               "activation memory overflows at tensor %zu '%.*s' (%zu bytes)", t,
               static_cast<int>(tensor.name.size()), tensor.name.data(), bytes);
    offsets[t] = total;
    total = (total + bytes + kArenaAlignment - 1) / kArenaAlignment * kArenaAlignment;
  }

  Arena arena;
  arena.bytes_ = total;
  // aligned_alloc needs a size that is a multiple of the alignment (total is) and non-zero.
  auto* memory = static_cast<std::byte*>(
      std::aligned_alloc(kArenaAlignment, total > 0 ? total : kArenaAlignment));
  TLV_ENSURE(memory != nullptr, ErrorCode::kOutOfMemory,
             "cannot allocate %zu bytes of activation memory", total);
  arena.memory_.reset(memory);
  // Zero-filled so reading a tensor before the first invoke() is deterministic.
  std::memset(memory, 0, total);

  arena.slots_.resize(graph.tensors.size());
  for (size_t t = 0; t < graph.tensors.size(); ++t) {
    const Tensor& tensor = graph.tensors[t];
    if (!tensor.is_constant()) arena.slots_[t] = {memory + offsets[t], tensor.bytes()};
  }
  return arena;
}

}  // namespace tlvlink::reference
