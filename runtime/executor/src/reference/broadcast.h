#pragma once
#ifndef TLVLINK_EXECUTOR_PRIVATE
#error "broadcast.h is internal to runtime/executor: include the public tlvlink/... headers instead"
#endif
// numpy broadcasting for the binary ops: both inputs and the output are viewed as rank-6
// (dimensions aligned from the right, missing ones are 1); a broadcast input dimension gets
// stride 0 so the same element is read along it.

#include <array>
#include <cstddef>
#include <cstdint>

#include "tlvlink/graph.h"

namespace tlvlink::reference {

struct Broadcast {
  static constexpr size_t kRank = Shape::kMaxRank;
  std::array<int32_t, kRank> dims{};  // output dimensions
  std::array<size_t, kRank> a_stride{}, b_stride{};
};

Broadcast make_broadcast(const Shape& a, const Shape& b, const Shape& out);

// Calls f(out_index, a_index, b_index) for every output element in row-major order.
template <typename F>
void for_each_broadcast(const Broadcast& bc, F&& f) {
  const auto& d = bc.dims;
  const auto& sa = bc.a_stride;
  const auto& sb = bc.b_stride;
  size_t o = 0;
  for (int32_t i0 = 0; i0 < d[0]; ++i0) {
    for (int32_t i1 = 0; i1 < d[1]; ++i1) {
      for (int32_t i2 = 0; i2 < d[2]; ++i2) {
        for (int32_t i3 = 0; i3 < d[3]; ++i3) {
          for (int32_t i4 = 0; i4 < d[4]; ++i4) {
            const size_t a4 = i0 * sa[0] + i1 * sa[1] + i2 * sa[2] + i3 * sa[3] + i4 * sa[4];
            const size_t b4 = i0 * sb[0] + i1 * sb[1] + i2 * sb[2] + i3 * sb[3] + i4 * sb[4];
            for (int32_t i5 = 0; i5 < d[5]; ++i5) f(o++, a4 + i5 * sa[5], b4 + i5 * sb[5]);
          }
        }
      }
    }
  }
}

}  // namespace tlvlink::reference
