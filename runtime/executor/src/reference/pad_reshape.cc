// Pad (constant, any rank up to 6) and Reshape. Both keep their input's quantization
// (validated), so int8 is handled as raw values; int8 padding is quantize_value(pad value).
#include <array>
#include <cstdint>
#include <cstring>

#include "reference/kernels.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::reference {
namespace {

constexpr size_t kRank = Shape::kMaxRank;

// Dimensions of `s` padded on the left with 1s to rank 6.
std::array<size_t, kRank> dims6(const Shape& s) {
  std::array<size_t, kRank> d;
  d.fill(1);
  for (size_t i = 0; i < s.rank; ++i) d[kRank - s.rank + i] = static_cast<size_t>(s.dims[i]);
  return d;
}

template <typename T>
void pad(const OpArgs& a, T value) {
  const PadParams& p = a.op->get<PadParams>();
  const size_t rank = a.in[0]->shape.rank;
  const std::array<size_t, kRank> in = dims6(a.in[0]->shape), out = dims6(a.out->shape);
  std::array<size_t, kRank> before{};
  for (size_t i = 0; i < rank; ++i) before[kRank - rank + i] = static_cast<size_t>(p.before[i]);

  const T* x = a.input<T>(0);
  T* y = a.output<T>();
  const size_t total = a.out->shape.elements();
  for (size_t i = 0; i < total; ++i) y[i] = value;

  // Copy each innermost input row to its place in the output.
  std::array<size_t, kRank> idx{};  // input index over the outer 5 dimensions
  const size_t rows = a.in[0]->shape.elements() / in[5];
  for (size_t r = 0; r < rows; ++r) {
    size_t o = 0;
    for (size_t d = 0; d < kRank; ++d) o = o * out[d] + idx[d] + before[d];
    std::memcpy(y + o, x + r * in[5], in[5] * sizeof(T));
    for (size_t d = kRank - 1; d-- > 0;) {  // odometer over dimensions 4..0
      if (++idx[d] < in[d]) break;
      idx[d] = 0;
    }
  }
}

void pad_f32(const OpArgs& a) { pad<float>(a, a.op->get<PadParams>().value); }

void pad_qs8(const OpArgs& a) {
  const Tensor& t = *a.out;
  pad<int8_t>(
      a, quantize_value(a.op->get<PadParams>().value, t.quant.scale[0], t.quant.zero_point[0]));
}

void reshape(const OpArgs& a) { std::memcpy(a.out_data, a.in_data[0], a.out->bytes()); }

}  // namespace

Kernel select_pad_reshape(const OpArgs& a) {
  const DType dtype = a.in[0]->dtype;
  if (a.op->type == OpType::kReshape) return reshape;  // any dtype: a plain copy
  if (a.op->type != OpType::kPad) return nullptr;
  if (dtype == DType::kFloat32) return pad_f32;
  if (dtype == DType::kInt8) return pad_qs8;
  return nullptr;
}

}  // namespace tlvlink::reference
