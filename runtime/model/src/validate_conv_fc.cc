// Conv2D and FullyConnected: shapes, dtypes, and the int8 constraints of quantization.md
// (weights in [-127,127], bias scale = s_in*s_w[c], requantization multiplier range,
// int32 accumulator bound).

#include <cmath>
#include <cstdlib>

#include "model_internal.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::model_internal {
namespace {

// Bias scales are written as float(s_in * s_w[c]); allow for the writer rounding differently.
constexpr double kBiasScaleRelTolerance = 1e-4;
// Largest |x_q - zp_x| for int8 activations (x = 127, zp = -128).
constexpr int64_t kMaxCenteredInput = 255;

int32_t dim(const Tensor& t, size_t i) { return t.shape.dims[i]; }

Status check_quantized(const Graph& graph, size_t op_index, const Operator& op, int32_t cout,
                       int64_t k) {
  const Label who = op_label(graph, op_index);
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& w = graph.tensor(op.inputs[1]);
  const Tensor& out = graph.tensor(op.output);
  TLV_ENSURE(w.dtype == DType::kInt8 && out.dtype == DType::kInt8, ErrorCode::kModelInvalidOperator,
             "%s with int8 input needs int8 weights and output, got %s and %s", who.text,
             dtype_name(w.dtype), dtype_name(out.dtype));
  TLV_ENSURE(!w.quant.per_channel() || w.quant.axis == 0, ErrorCode::kModelInvalidOperator,
             "%s weights are quantized along axis %d; the output-channel axis is 0", who.text,
             w.quant.axis);
  TLV_ENSURE(!out.quant.per_channel(), ErrorCode::kModelInvalidOperator,
             "%s output must be quantized per-tensor", who.text);
  // XNNPACK's qc8 and qs8 weights are symmetric; a non-zero weight zero point would be ignored.
  for (size_t i = 0; i < w.quant.zero_point.size(); ++i) {
    TLV_ENSURE(w.quant.zero_point[i] == 0, ErrorCode::kModelInvalidOperator,
               "%s weights %s have zero_point[%zu] = %d; int8 weights must be symmetric (0)",
               who.text, tensor_label(graph, op.inputs[1]).text, i, w.quant.zero_point[i]);
  }
  const auto* wq = reinterpret_cast<const int8_t*>(w.data.data());
  const size_t per_channel = w.shape.elements() / static_cast<size_t>(cout);
  const float s_in = in.quant.scale[0];  // per-tensor: loader.cc checks every activation
  const float s_out = out.quant.scale[0];
  const Tensor* bias = op.inputs[2] == kNoTensor ? nullptr : &graph.tensor(op.inputs[2]);
  if (bias != nullptr) {
    TLV_ENSURE(bias->dtype == DType::kInt32 && bias->quant.quantized(),
               ErrorCode::kModelInvalidOperator, "%s int8 needs an int32 quantized bias, %s is %s",
               who.text, tensor_label(graph, op.inputs[2]).text, dtype_name(bias->dtype));
    TLV_ENSURE(bias->quant.scale.size() == w.quant.scale.size(), ErrorCode::kModelInvalidOperator,
               "%s bias has %zu scales, weights have %zu", who.text, bias->quant.scale.size(),
               w.quant.scale.size());
  }
  const auto* bq = bias ? reinterpret_cast<const int32_t*>(bias->data.data()) : nullptr;
  for (int32_t c = 0; c < cout; ++c) {
    const double s_w =
        static_cast<double>(w.quant.scale[w.quant.per_channel() ? static_cast<size_t>(c) : 0]);
    const double multiplier = static_cast<double>(s_in) * s_w / static_cast<double>(s_out);
    TLV_ENSURE(multiplier >= kMinRequantMultiplier && multiplier < kMaxRequantMultiplier,
               ErrorCode::kModelInvalidOperator,
               "%s channel %d requantization multiplier s_in*s_w/s_out = %g is outside "
               "[2^-31, 256): the output would be flushed to zero or rejected",
               who.text, c, multiplier);
    int64_t abs_sum = 0;
    for (size_t i = 0; i < per_channel; ++i) {
      const int8_t v = wq[static_cast<size_t>(c) * per_channel + i];
      TLV_ENSURE(v >= kWeightMin, ErrorCode::kModelInvalidOperator,
                 "%s weight %zu of channel %d is -128; weights must be in [-127, 127]", who.text, i,
                 c);
      abs_sum += std::abs(static_cast<int32_t>(v));
    }
    int64_t abs_bias = 0;
    if (bq != nullptr) {
      const size_t bc = bias->quant.per_channel() ? static_cast<size_t>(c) : 0;
      const double expected = static_cast<double>(s_in) * s_w;
      const double actual = static_cast<double>(bias->quant.scale[bc]);
      TLV_ENSURE(std::fabs(actual - expected) <= kBiasScaleRelTolerance * expected,
                 ErrorCode::kModelInvalidOperator,
                 "%s bias scale[%zu] = %g, expected input_scale*weight_scale = %g", who.text, bc,
                 actual, expected);
      abs_bias = std::llabs(static_cast<long long>(bq[c]));
    }
    const int64_t bound = abs_bias + kMaxCenteredInput * abs_sum;
    TLV_ENSURE(bound < (int64_t{1} << 31), ErrorCode::kModelInvalidOperator,
               "%s channel %d worst-case accumulator %lld (K=%lld) exceeds int32", who.text, c,
               static_cast<long long>(bound), static_cast<long long>(k));
  }
  return {};
}

Status check_common(const Graph& graph, size_t op_index, const Operator& op, int32_t cout,
                    int64_t k) {
  const Label who = op_label(graph, op_index);
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& w = graph.tensor(op.inputs[1]);
  const Tensor& out = graph.tensor(op.output);
  TLV_ENSURE(w.is_constant(), ErrorCode::kModelInvalidOperator, "%s weights %s must be constant",
             who.text, tensor_label(graph, op.inputs[1]).text);
  if (op.inputs[2] != kNoTensor) {
    const Tensor& b = graph.tensor(op.inputs[2]);
    TLV_ENSURE(b.is_constant() && b.shape.rank == 1 && dim(b, 0) == cout,
               ErrorCode::kModelInvalidOperator, "%s bias %s must be a constant [%d], is %s",
               who.text, tensor_label(graph, op.inputs[2]).text, cout, shape_label(b.shape).text);
  }
  if (in.dtype == DType::kFloat32) {
    const bool bias_ok =
        op.inputs[2] == kNoTensor || graph.tensor(op.inputs[2]).dtype == DType::kFloat32;
    TLV_ENSURE(w.dtype == DType::kFloat32 && out.dtype == DType::kFloat32 && bias_ok,
               ErrorCode::kModelInvalidOperator,
               "%s float32 input needs float32 weights, bias and output", who.text);
    return {};
  }
  TLV_ENSURE(in.dtype == DType::kInt8, ErrorCode::kModelInvalidOperator,
             "%s input dtype %s is not supported (float32 or int8)", who.text,
             dtype_name(in.dtype));
  return check_quantized(graph, op_index, op, cout, k);
}

Status validate_conv(const Graph& graph, size_t op_index, const Operator& op) {
  const Label who = op_label(graph, op_index);
  const auto& p = op.get<Conv2DParams>();
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& w = graph.tensor(op.inputs[1]);
  const Tensor& out = graph.tensor(op.output);
  TLV_ENSURE(in.shape.rank == 4 && w.shape.rank == 4 && out.shape.rank == 4,
             ErrorCode::kModelInvalidOperator,
             "%s needs rank-4 input, weights and output (NHWC / OHWI), got %s %s %s", who.text,
             shape_label(in.shape).text, shape_label(w.shape).text, shape_label(out.shape).text);
  const int32_t cin = dim(in, 3), cout = dim(w, 0);
  TLV_ENSURE(cin % p.groups == 0 && cout % p.groups == 0, ErrorCode::kModelInvalidOperator,
             "%s groups %d must divide input channels %d and output channels %d", who.text,
             p.groups, cin, cout);
  TLV_ENSURE(dim(w, 1) == p.kernel_h && dim(w, 2) == p.kernel_w && dim(w, 3) == cin / p.groups,
             ErrorCode::kModelInvalidOperator,
             "%s weights %s do not match kernel %dx%d with %d input channels per group", who.text,
             shape_label(w.shape).text, p.kernel_h, p.kernel_w, cin / p.groups);
  const int64_t eff_h = int64_t{p.dilation_h} * (p.kernel_h - 1) + 1;
  const int64_t eff_w = int64_t{p.dilation_w} * (p.kernel_w - 1) + 1;
  const int64_t padded_h = int64_t{dim(in, 1)} + p.pad_top + p.pad_bottom;
  const int64_t padded_w = int64_t{dim(in, 2)} + p.pad_left + p.pad_right;
  TLV_ENSURE(padded_h >= eff_h && padded_w >= eff_w, ErrorCode::kModelInvalidOperator,
             "%s dilated kernel %lldx%lld is larger than the padded input %lldx%lld", who.text,
             static_cast<long long>(eff_h), static_cast<long long>(eff_w),
             static_cast<long long>(padded_h), static_cast<long long>(padded_w));
  const int64_t oh = (padded_h - eff_h) / p.stride_h + 1;
  const int64_t ow = (padded_w - eff_w) / p.stride_w + 1;
  TLV_ENSURE(
      dim(out, 0) == dim(in, 0) && dim(out, 1) == oh && dim(out, 2) == ow && dim(out, 3) == cout,
      ErrorCode::kModelInvalidOperator, "%s output is %s, expected [%d,%lld,%lld,%d]", who.text,
      shape_label(out.shape).text, dim(in, 0), static_cast<long long>(oh),
      static_cast<long long>(ow), cout);
  return check_common(graph, op_index, op, cout, int64_t{p.kernel_h} * p.kernel_w * dim(w, 3));
}

Status validate_fc(const Graph& graph, size_t op_index, const Operator& op) {
  const Label who = op_label(graph, op_index);
  const Tensor& in = graph.tensor(op.inputs[0]);
  const Tensor& w = graph.tensor(op.inputs[1]);
  const Tensor& out = graph.tensor(op.output);
  TLV_ENSURE(in.shape.rank == 2 && w.shape.rank == 2 && out.shape.rank == 2,
             ErrorCode::kModelInvalidOperator,
             "%s needs input [N,Cin], weights [Cout,Cin], output [N,Cout]; got %s %s %s", who.text,
             shape_label(in.shape).text, shape_label(w.shape).text, shape_label(out.shape).text);
  TLV_ENSURE(dim(w, 1) == dim(in, 1) && dim(out, 0) == dim(in, 0) && dim(out, 1) == dim(w, 0),
             ErrorCode::kModelInvalidOperator, "%s shapes %s x %s -> %s are inconsistent", who.text,
             shape_label(in.shape).text, shape_label(w.shape).text, shape_label(out.shape).text);
  return check_common(graph, op_index, op, dim(w, 0), dim(w, 1));
}

}  // namespace

Status validate_conv_fc(const Graph& graph, size_t op_index) {
  const Operator& op = graph.operators[op_index];
  return op.type == OpType::kConv2D ? validate_conv(graph, op_index, op)
                                    : validate_fc(graph, op_index, op);
}

}  // namespace tlvlink::model_internal
