// Element-wise ops: Add/Mul (numpy broadcasting), Clamp, Sigmoid, Quantize, Dequantize.

#include <algorithm>

#include "model_internal.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::model_internal {
namespace {

// Sigmoid's int8 output is fixed so (0, 1) maps onto the whole int8 range (XNNPACK requires it).
constexpr float kSigmoidOutputScale = 1.0f / 256.0f;
constexpr int32_t kSigmoidOutputZeroPoint = -128;

Status check_per_tensor_int8(const Graph& graph, size_t op_index, int32_t t) {
  const Tensor& x = graph.tensor(t);
  TLV_ENSURE(x.dtype == DType::kInt8 && !x.quant.per_channel(), ErrorCode::kModelInvalidOperator,
             "%s: %s must be int8 quantized per-tensor", op_label(graph, op_index).text,
             tensor_label(graph, t).text);
  return {};
}

Status validate_binary(const Graph& graph, size_t op_index, const Operator& op) {
  const Label who = op_label(graph, op_index);
  const Tensor& a = graph.tensor(op.inputs[0]);
  const Tensor& b = graph.tensor(op.inputs[1]);
  const Tensor& out = graph.tensor(op.output);
  const size_t rank = std::max(a.shape.rank, b.shape.rank);
  TLV_ENSURE(out.shape.rank == rank, ErrorCode::kModelInvalidOperator,
             "%s output rank %zu, expected %zu", who.text, out.shape.rank, rank);
  for (size_t i = 0; i < rank; ++i) {  // align dimensions from the right
    const int32_t da = i < rank - a.shape.rank ? 1 : a.shape.dims[i - (rank - a.shape.rank)];
    const int32_t db = i < rank - b.shape.rank ? 1 : b.shape.dims[i - (rank - b.shape.rank)];
    TLV_ENSURE(da == db || da == 1 || db == 1, ErrorCode::kModelInvalidOperator,
               "%s cannot broadcast %s with %s", who.text, shape_label(a.shape).text,
               shape_label(b.shape).text);
    TLV_ENSURE(out.shape.dims[i] == std::max(da, db), ErrorCode::kModelInvalidOperator,
               "%s output %s does not match the broadcast of %s and %s", who.text,
               shape_label(out.shape).text, shape_label(a.shape).text, shape_label(b.shape).text);
  }
  if (a.dtype == DType::kFloat32) {
    TLV_ENSURE(b.dtype == DType::kFloat32 && out.dtype == DType::kFloat32,
               ErrorCode::kModelInvalidOperator, "%s mixes float32 with %s/%s", who.text,
               dtype_name(b.dtype), dtype_name(out.dtype));
    return {};
  }
  TLV_TRY(check_per_tensor_int8(graph, op_index, op.inputs[0]));
  TLV_TRY(check_per_tensor_int8(graph, op_index, op.inputs[1]));
  TLV_TRY(check_per_tensor_int8(graph, op_index, op.output));
  const double s_out = static_cast<double>(out.quant.scale[0]);
  const double ratios[2] = {
      op.type == OpType::kAdd
          ? static_cast<double>(a.quant.scale[0]) / s_out
          : static_cast<double>(a.quant.scale[0]) * static_cast<double>(b.quant.scale[0]) / s_out,
      op.type == OpType::kAdd ? static_cast<double>(b.quant.scale[0]) / s_out : 1.0};
  for (double r : ratios) {
    TLV_ENSURE(r >= kMinRequantMultiplier && r < kMaxRequantMultiplier,
               ErrorCode::kModelInvalidOperator,
               "%s requantization multiplier %g is outside [2^-31, 256)", who.text, r);
  }
  return {};
}

}  // namespace

Status validate_elementwise(const Graph& graph, size_t op_index) {
  const Operator& op = graph.operators[op_index];
  if (op.type == OpType::kAdd || op.type == OpType::kMul)
    return validate_binary(graph, op_index, op);

  const Label who = op_label(graph, op_index);
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& out = graph.tensor(op.output);
  TLV_ENSURE(in.shape == out.shape, ErrorCode::kModelInvalidOperator,
             "%s input %s and output %s must have the same shape", who.text,
             shape_label(in.shape).text, shape_label(out.shape).text);
  switch (op.type) {
    case OpType::kQuantize:
      TLV_ENSURE(in.dtype == DType::kFloat32, ErrorCode::kModelInvalidOperator,
                 "%s input must be float32, is %s", who.text, dtype_name(in.dtype));
      return check_per_tensor_int8(graph, op_index, op.output);
    case OpType::kDequantize:
      TLV_ENSURE(out.dtype == DType::kFloat32, ErrorCode::kModelInvalidOperator,
                 "%s output must be float32, is %s", who.text, dtype_name(out.dtype));
      return check_per_tensor_int8(graph, op_index, op.inputs[0]);
    case OpType::kClamp:
      TLV_ENSURE(in.dtype == out.dtype && (in.dtype == DType::kFloat32 || in.dtype == DType::kInt8),
                 ErrorCode::kModelInvalidOperator, "%s maps %s to %s", who.text,
                 dtype_name(in.dtype), dtype_name(out.dtype));
      if (in.dtype == DType::kInt8) {
        TLV_TRY(check_per_tensor_int8(graph, op_index, op.inputs[0]));
        TLV_ENSURE(same_quantization(in, out), ErrorCode::kModelInvalidOperator,
                   "%s output must keep its input's scale and zero point", who.text);
      }
      return {};
    case OpType::kSigmoid:
      if (in.dtype == DType::kFloat32) {
        TLV_ENSURE(out.dtype == DType::kFloat32, ErrorCode::kModelInvalidOperator,
                   "%s maps float32 to %s", who.text, dtype_name(out.dtype));
        return {};
      }
      TLV_TRY(check_per_tensor_int8(graph, op_index, op.inputs[0]));
      TLV_TRY(check_per_tensor_int8(graph, op_index, op.output));
      TLV_ENSURE(out.quant.scale[0] == kSigmoidOutputScale &&
                     out.quant.zero_point[0] == kSigmoidOutputZeroPoint,
                 ErrorCode::kModelInvalidOperator,
                 "%s int8 output must have scale 1/256 and zero point -128, has %g and %d",
                 who.text, static_cast<double>(out.quant.scale[0]), out.quant.zero_point[0]);
      return {};
    default: return {};
  }
}

}  // namespace tlvlink::model_internal
