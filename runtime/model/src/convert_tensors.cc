// Tensors: every field of every tensor is checked before the Graph refers to it.

#include <bit>
#include <cmath>

#include "model_internal.h"
#include "tlvlink/model.h"

namespace tlvlink::model_internal {
namespace {

static_assert(std::endian::native == std::endian::little,
              "tlvlink reads flatbuffer vectors in place: little-endian targets only");

// Largest activation or constant a model may declare (documented in runtime/README.md).
constexpr size_t kMaxTensorBytes = size_t{1} << 31;
constexpr int32_t kMaxDim = 1 << 24;

Status check_shape(const fb::Tensor& t, Graph& graph, int32_t index, Tensor& out) {
  const Label who = tensor_label(graph, index);
  TLV_ENSURE(t.shape() != nullptr && t.shape()->size() >= 1, ErrorCode::kModelInvalidTensor,
             "%s has no shape (rank 0 is not supported)", who.text);
  TLV_ENSURE(t.shape()->size() <= Shape::kMaxRank, ErrorCode::kModelInvalidTensor,
             "%s has rank %u, the limit is %zu", who.text, t.shape()->size(), Shape::kMaxRank);
  out.shape.rank = t.shape()->size();
  size_t bytes = dtype_size(out.dtype);
  for (size_t d = 0; d < out.shape.rank; ++d) {
    const int32_t dim = t.shape()->Get(static_cast<flatbuffers::uoffset_t>(d));
    TLV_ENSURE(dim >= 1 && dim <= kMaxDim, ErrorCode::kModelInvalidTensor,
               "%s dimension %zu is %d, must be in [1, %d]", who.text, d, dim, kMaxDim);
    out.shape.dims[d] = dim;
    bytes *= static_cast<size_t>(dim);
    TLV_ENSURE(bytes <= kMaxTensorBytes, ErrorCode::kModelInvalidTensor,
               "%s is larger than the %zu-byte tensor limit", who.text, kMaxTensorBytes);
  }
  return {};
}

Status check_quantization(const fb::Tensor& t, Graph& graph, int32_t index, Tensor& out) {
  const Label who = tensor_label(graph, index);
  const fb::Quantization* q = t.quantization();
  const bool has_scale = q != nullptr && q->scale() != nullptr && q->scale()->size() > 0;
  if (!has_scale) {
    TLV_ENSURE(out.dtype != DType::kInt8 && out.dtype != DType::kUInt8,
               ErrorCode::kModelInvalidTensor, "%s is %s but has no quantization parameters",
               who.text, dtype_name(out.dtype));
    return {};
  }
  TLV_ENSURE(out.dtype != DType::kFloat32, ErrorCode::kModelInvalidTensor,
             "%s is float32 but carries quantization parameters", who.text);
  const uint32_t n = q->scale()->size();
  TLV_ENSURE(q->zero_point() != nullptr && q->zero_point()->size() == n,
             ErrorCode::kModelInvalidTensor, "%s has %u scales but %u zero points", who.text, n,
             q->zero_point() ? q->zero_point()->size() : 0u);
  const int32_t axis = q->axis();
  if (axis < 0) {
    TLV_ENSURE(axis == -1 && n == 1, ErrorCode::kModelInvalidTensor,
               "%s is per-tensor (axis %d) but has %u scales", who.text, axis, n);
  } else {
    TLV_ENSURE(static_cast<size_t>(axis) < out.shape.rank, ErrorCode::kModelInvalidTensor,
               "%s quantization axis %d is out of range for rank %zu", who.text, axis,
               out.shape.rank);
    TLV_ENSURE(static_cast<int64_t>(n) == out.shape.dims[static_cast<size_t>(axis)],
               ErrorCode::kModelInvalidTensor, "%s has %u scales for %d channels along axis %d",
               who.text, n, out.shape.dims[static_cast<size_t>(axis)], axis);
  }
  for (uint32_t i = 0; i < n; ++i) {
    const float s = q->scale()->Get(i);
    TLV_ENSURE(std::isfinite(s) && s > 0.0f && std::isnormal(s), ErrorCode::kModelInvalidTensor,
               "%s scale[%u] = %g: scales must be finite, positive and normal (not denormal)",
               who.text, i, static_cast<double>(s));
    const int32_t zp = q->zero_point()->Get(i);
    int32_t lo = 0, hi = 0;
    if (out.dtype == DType::kInt8) lo = -128, hi = 127;
    if (out.dtype == DType::kUInt8) lo = 0, hi = 255;
    if (axis >= 0) lo = hi = 0;  // per-channel (weights, bias) is symmetric
    TLV_ENSURE(zp >= lo && zp <= hi, ErrorCode::kModelInvalidTensor,
               "%s zero_point[%u] = %d, must be in [%d, %d] for %s%s", who.text, i, zp, lo, hi,
               dtype_name(out.dtype), axis >= 0 ? " per-channel" : "");
  }
  out.quant.scale = {q->scale()->data(), n};
  out.quant.zero_point = {q->zero_point()->data(), n};
  out.quant.axis = axis;
  return {};
}

Status bind_data(const fb::Tensor& t, Buffers buffers, Graph& graph, int32_t index, Tensor& out) {
  if (t.buffer() == 0) return {};
  const Label who = tensor_label(graph, index);
  TLV_ENSURE(t.buffer() < buffers.size(), ErrorCode::kModelInvalidTensor,
             "%s refers to buffer %u, the model has %zu buffers", who.text, t.buffer(),
             buffers.size());
  const auto data = buffers[t.buffer()];
  TLV_ENSURE(data.size() == out.bytes(), ErrorCode::kModelInvalidTensor,
             "%s %s %s needs %zu bytes of data, buffer %u holds %zu", who.text,
             dtype_name(out.dtype), shape_label(out.shape).text, out.bytes(), t.buffer(),
             data.size());
  if (out.dtype == DType::kFloat32) {
    const auto* v = reinterpret_cast<const float*>(data.data());
    for (size_t i = 0; i < out.shape.elements(); ++i) {
      TLV_ENSURE(std::isfinite(v[i]), ErrorCode::kModelInvalidTensor,
                 "%s element %zu is %g: constants must be finite", who.text, i,
                 static_cast<double>(v[i]));
    }
  }
  out.data = data;
  return {};
}

}  // namespace

Status convert_tensors(const fb::Graph& fb_graph, Buffers buffers, Graph& graph) {
  const auto* tensors = fb_graph.tensors();
  TLV_ENSURE(tensors != nullptr && tensors->size() > 0, ErrorCode::kModelMalformed,
             "graph has no tensors");
  TLV_ENSURE(tensors->size() <= kMaxTensors, ErrorCode::kModelMalformed,
             "graph has %u tensors, the limit is %zu", tensors->size(), kMaxTensors);
  graph.tensors.resize(tensors->size());
  for (uint32_t i = 0; i < tensors->size(); ++i) {
    const auto index = static_cast<int32_t>(i);
    const fb::Tensor* t = tensors->Get(i);
    TLV_ENSURE(t != nullptr, ErrorCode::kModelMalformed, "tensor %u is missing", i);
    Tensor& out = graph.tensors[i];
    if (t->name() != nullptr) out.name = {t->name()->c_str(), t->name()->size()};
    const auto dtype = static_cast<int>(t->dtype());
    TLV_ENSURE(dtype >= 0 && dtype <= static_cast<int>(DType::kUInt8),
               ErrorCode::kModelInvalidTensor, "%s has unknown dtype %d",
               tensor_label(graph, index).text, dtype);
    out.dtype = static_cast<DType>(dtype);
    TLV_TRY(check_shape(*t, graph, index, out));
    TLV_TRY(check_quantization(*t, graph, index, out));
    TLV_TRY(bind_data(*t, buffers, graph, index, out));
  }
  return {};
}

}  // namespace tlvlink::model_internal
