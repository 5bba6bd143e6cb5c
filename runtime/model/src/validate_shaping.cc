// Layout ops: GlobalAveragePool, MaxPool2D, Pad, Reshape, ResizeBilinear. All but the average
// pool pass quantization through unchanged (quantization.md: pass-through ops share parameters).

#include <algorithm>

#include "model_internal.h"

namespace tlvlink::model_internal {
namespace {

Status check_dtypes(const Graph& graph, size_t op_index, const Tensor& in, const Tensor& out,
                    bool pass_through) {
  const Label who = op_label(graph, op_index);
  TLV_ENSURE(in.dtype == out.dtype && (in.dtype == DType::kFloat32 || in.dtype == DType::kInt8),
             ErrorCode::kModelInvalidOperator, "%s maps %s to %s (float32 or int8, unchanged)",
             who.text, dtype_name(in.dtype), dtype_name(out.dtype));
  if (in.dtype == DType::kInt8) {
    TLV_ENSURE(!in.quant.per_channel() && !out.quant.per_channel(),
               ErrorCode::kModelInvalidOperator, "%s int8 tensors must be per-tensor", who.text);
    TLV_ENSURE(!pass_through || same_quantization(in, out), ErrorCode::kModelInvalidOperator,
               "%s output must keep its input's scale and zero point", who.text);
  }
  return {};
}

}  // namespace

Status validate_shaping(const Graph& graph, size_t op_index) {
  const Operator& op = graph.operators[op_index];
  const Label who = op_label(graph, op_index);
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& out = graph.tensor(op.output);
  const Shape& s = in.shape;
  const Shape& o = out.shape;

  switch (op.type) {
    case OpType::kGlobalAveragePool:
      TLV_ENSURE(
          s.rank == 4 && o.rank == 4 && o[0] == s[0] && o[1] == 1 && o[2] == 1 && o[3] == s[3],
          ErrorCode::kModelInvalidOperator, "%s maps %s to %s, expected [N,H,W,C] -> [N,1,1,C]",
          who.text, shape_label(s).text, shape_label(o).text);
      return check_dtypes(graph, op_index, in, out, /*pass_through=*/false);
    case OpType::kMaxPool2D: {
      const auto& p = op.get<Pool2DParams>();
      TLV_ENSURE(s.rank == 4 && o.rank == 4, ErrorCode::kModelInvalidOperator,
                 "%s needs rank-4 tensors", who.text);
      const int64_t ph = int64_t{s[1]} + p.pad_top + p.pad_bottom;
      const int64_t pw = int64_t{s[2]} + p.pad_left + p.pad_right;
      TLV_ENSURE(ph >= p.pool_h && pw >= p.pool_w, ErrorCode::kModelInvalidOperator,
                 "%s pool %dx%d is larger than the padded input", who.text, p.pool_h, p.pool_w);
      const int64_t oh = (ph - p.pool_h) / p.stride_h + 1, ow = (pw - p.pool_w) / p.stride_w + 1;
      TLV_ENSURE(o[0] == s[0] && o[1] == oh && o[2] == ow && o[3] == s[3],
                 ErrorCode::kModelInvalidOperator, "%s output %s, expected [%d,%lld,%lld,%d]",
                 who.text, shape_label(o).text, s[0], static_cast<long long>(oh),
                 static_cast<long long>(ow), s[3]);
      return check_dtypes(graph, op_index, in, out, true);
    }
    case OpType::kPad: {
      const auto& p = op.get<PadParams>();
      TLV_ENSURE(o.rank == s.rank, ErrorCode::kModelInvalidOperator, "%s changes the rank",
                 who.text);
      for (size_t d = 0; d < s.rank; ++d) {
        TLV_ENSURE(int64_t{o[d]} == int64_t{s[d]} + p.before[d] + p.after[d],
                   ErrorCode::kModelInvalidOperator,
                   "%s output dimension %zu is %d, expected %d + %d + %d", who.text, d, o[d], s[d],
                   p.before[d], p.after[d]);
      }
      return check_dtypes(graph, op_index, in, out, true);
    }
    case OpType::kReshape:
      TLV_ENSURE(s.elements() == o.elements(), ErrorCode::kModelInvalidOperator,
                 "%s cannot reshape %s (%zu elements) to %s (%zu)", who.text, shape_label(s).text,
                 s.elements(), shape_label(o).text, o.elements());
      return check_dtypes(graph, op_index, in, out, true);
    case OpType::kResizeBilinear:
      TLV_ENSURE(s.rank == 4 && o.rank == 4 && o[0] == s[0] && o[3] == s[3],
                 ErrorCode::kModelInvalidOperator,
                 "%s maps %s to %s; batch and channels must be kept", who.text, shape_label(s).text,
                 shape_label(o).text);
      return check_dtypes(graph, op_index, in, out, true);
    default: return Error::make(ErrorCode::kModelInvalidOperator, "%s: no validator", who.text);
  }
}

}  // namespace tlvlink::model_internal
