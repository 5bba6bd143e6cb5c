#include "reference/broadcast.h"

namespace tlvlink::reference {
namespace {

// Row-major strides of `s` padded on the left to rank 6, with 0 where the dimension is 1.
std::array<size_t, Broadcast::kRank> broadcast_strides(const Shape& s) {
  std::array<size_t, Broadcast::kRank> strides{};
  const size_t offset = Broadcast::kRank - s.rank;
  size_t stride = 1;
  for (size_t i = s.rank; i-- > 0;) {
    strides[offset + i] = s.dims[i] == 1 ? 0 : stride;
    stride *= static_cast<size_t>(s.dims[i]);
  }
  return strides;
}

}  // namespace

Broadcast make_broadcast(const Shape& a, const Shape& b, const Shape& out) {
  Broadcast bc;
  bc.dims.fill(1);
  const size_t offset = Broadcast::kRank - out.rank;
  for (size_t i = 0; i < out.rank; ++i) bc.dims[offset + i] = out.dims[i];
  bc.a_stride = broadcast_strides(a);
  bc.b_stride = broadcast_strides(b);
  return bc;
}

}  // namespace tlvlink::reference
