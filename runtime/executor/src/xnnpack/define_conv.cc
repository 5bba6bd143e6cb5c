// Conv2D and FullyConnected as XNNPACK nodes, with weights in the layout each node expects.
//
// Model layout: conv weights OHWI [Cout, KH, KW, Cin/groups], FC weights [Cout, Cin], per-channel
// scales on axis 0, int32 bias with scale in_scale * w_scale[c].
// - Dense / grouped conv: xnn_define_convolution_2d takes [groups * Cout/g, KH, KW, Cin/g]: as is.
// - Depthwise (groups == Cin > 1): xnn_define_depthwise_convolution_2d takes [1, KH, KW, Cout]
//   with the channel on dim 3: transposed once here into memory the executor owns.
// - FC fp32: xnn_define_fully_connected. FC int8 with per-channel weights is rejected by this
//   XNNPACK (invalid_parameter), so it runs as a 1x1 convolution on an [N,1,1,Cin] view of its
//   input, between two static reshapes (copies of N*C bytes).
#include <cstring>

#include "xnnpack/define_ops.h"

namespace tlvlink::xnn {
namespace {

struct ConvTensors {
  const Tensor& input;
  const Tensor& weights;
  int32_t weights_index;
  int32_t bias_index;  // kNoTensor when absent
};

ConvTensors conv_tensors(const Graph& graph, const Operator& op) {
  const int32_t bias = op.input_count > 2 ? op.inputs[2] : kNoTensor;
  return {graph.tensor(op.inputs[0]), graph.tensor(op.inputs[1]), op.inputs[1], bias};
}

// Per-output-channel weight scales (a per-tensor scale is repeated), owned by the executor
// when they had to be expanded.
Result<std::span<const float>> weight_scales(ValueTable& values, const Tensor& w, size_t cout) {
  if (w.quant.per_channel()) return w.quant.scale;
  TLV_ASSIGN_OR_RETURN(std::span<float> scales, values.memory().allocate_array<float>(cout));
  for (float& s : scales) s = w.quant.scale[0];
  return std::span<const float>(scales);
}

// Weights as fp32 or qcint8 with the given dims / channel dim; `data` is either the model's
// bytes or a transposed copy the executor owns.
Result<uint32_t> define_weights(ValueTable& values, const ConvTensors& t, const Dims& dims,
                                size_t channel_dim, size_t cout, const void* data,
                                const NodeRef& who) {
  ValueDesc desc;
  desc.dims = dims.span();
  desc.data = data;
  if (t.weights.dtype == DType::kInt8) {
    for (int32_t zp : t.weights.quant.zero_point) {
      TLV_ENSURE(zp == 0, ErrorCode::kModelUnsupported,
                 "operator '%.*s' (#%d): XNNPACK needs symmetric weights (zero point 0), "
                 "got %d",
                 static_cast<int>(who.name.size()), who.name.data(), who.index, zp);
    }
    TLV_ASSIGN_OR_RETURN(desc.channel_scales, weight_scales(values, t.weights, cout));
    desc.type = ValueType::kQCInt8;
    desc.channel_dim = channel_dim;
  }
  return values.define_static(desc, who);
}

// Bias as fp32 or qcint32 (scale in_scale * w_scale[c]); a zero bias when the model has none.
Result<uint32_t> define_bias(ValueTable& values, const ConvTensors& t, size_t cout,
                             const NodeRef& who) {
  Dims dims;
  dims.rank = 1;
  dims.d[0] = cout;
  ValueDesc desc;
  desc.dims = dims.span();
  if (t.bias_index != kNoTensor) {
    desc.data = values.graph().tensor(t.bias_index).data.data();
  } else {
    TLV_ASSIGN_OR_RETURN(std::span<std::byte> zeros, values.memory().allocate(cout * 4));
    desc.data = zeros.data();
  }
  if (t.weights.dtype == DType::kInt8) {
    TLV_ASSIGN_OR_RETURN(std::span<const float> w_scales, weight_scales(values, t.weights, cout));
    TLV_ASSIGN_OR_RETURN(std::span<float> scales, values.memory().allocate_array<float>(cout));
    for (size_t c = 0; c < cout; ++c) scales[c] = t.input.quant.scale[0] * w_scales[c];
    desc.type = ValueType::kQCInt32;
    desc.channel_scales = scales;
    desc.channel_dim = 0;
  }
  return values.define_static(desc, who);
}

// [Cout, KH, KW, 1] -> [1, KH, KW, Cout], element size 1 (int8) or 4 (fp32).
Result<const void*> transpose_depthwise(ValueTable& values, const Tensor& w) {
  const size_t cout = static_cast<size_t>(w.shape[0]);
  const size_t taps = static_cast<size_t>(w.shape[1]) * static_cast<size_t>(w.shape[2]);
  const size_t elem = dtype_size(w.dtype);
  TLV_ASSIGN_OR_RETURN(std::span<std::byte> out, values.memory().allocate(w.data.size()));
  for (size_t c = 0; c < cout; ++c) {
    for (size_t k = 0; k < taps; ++k) {
      std::memcpy(out.data() + (k * cout + c) * elem, w.data.data() + (c * taps + k) * elem, elem);
    }
  }
  return static_cast<const void*>(out.data());
}

}  // namespace

Status define_conv2d(ValueTable& values, int32_t op_index) {
  const Graph& graph = values.graph();
  const Operator& op = graph.operators[static_cast<size_t>(op_index)];
  const Conv2DParams& p = op.get<Conv2DParams>();
  const NodeRef who = operator_ref(graph, op_index);
  const ConvTensors t = conv_tensors(graph, op);
  const size_t cin = static_cast<size_t>(t.input.shape[3]);
  const size_t cout = static_cast<size_t>(t.weights.shape[0]);
  const bool depthwise = p.groups > 1 && static_cast<size_t>(p.groups) == cin;

  Conv2DSpec spec;
  spec.pad_top = static_cast<uint32_t>(p.pad_top);
  spec.pad_right = static_cast<uint32_t>(p.pad_right);
  spec.pad_bottom = static_cast<uint32_t>(p.pad_bottom);
  spec.pad_left = static_cast<uint32_t>(p.pad_left);
  spec.kernel_h = static_cast<uint32_t>(p.kernel_h);
  spec.kernel_w = static_cast<uint32_t>(p.kernel_w);
  spec.stride_h = static_cast<uint32_t>(p.stride_h);
  spec.stride_w = static_cast<uint32_t>(p.stride_w);
  spec.dilation_h = static_cast<uint32_t>(p.dilation_h);
  spec.dilation_w = static_cast<uint32_t>(p.dilation_w);
  spec.output_min = activation_min(p.activation);
  spec.output_max = activation_max(p.activation);
  TLV_ASSIGN_OR_RETURN(spec.input, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(spec.output, values.value(op.output));
  TLV_ASSIGN_OR_RETURN(spec.bias, define_bias(values, t, cout, who));

  Dims wdims = dims_of(t.weights.shape);
  if (depthwise) {
    wdims.d = {1, wdims.d[1], wdims.d[2], cout};
    TLV_ASSIGN_OR_RETURN(const void* data, transpose_depthwise(values, t.weights));
    TLV_ASSIGN_OR_RETURN(spec.filter,
                         define_weights(values, t, wdims, /*channel_dim=*/3, cout, data, who));
    spec.depth_multiplier = static_cast<uint32_t>(cout / cin);
    spec.group_input_channels = cin;
    return values.subgraph().define_depthwise_convolution_2d(spec, who);
  }
  TLV_ASSIGN_OR_RETURN(spec.filter, define_weights(values, t, wdims, /*channel_dim=*/0, cout,
                                                   t.weights.data.data(), who));
  spec.groups = static_cast<uint32_t>(p.groups);
  spec.group_input_channels = cin / static_cast<size_t>(p.groups);
  spec.group_output_channels = cout / static_cast<size_t>(p.groups);
  return values.subgraph().define_convolution_2d(spec, who);
}

Status define_fully_connected(ValueTable& values, int32_t op_index) {
  const Graph& graph = values.graph();
  const Operator& op = graph.operators[static_cast<size_t>(op_index)];
  const Activation act = op.get<FullyConnectedParams>().activation;
  const NodeRef who = operator_ref(graph, op_index);
  const ConvTensors t = conv_tensors(graph, op);
  const Tensor& output = graph.tensor(op.output);
  const size_t cout = static_cast<size_t>(t.weights.shape[0]);
  const size_t cin = static_cast<size_t>(t.weights.shape[1]);
  const size_t batch = t.input.shape.elements() / cin;

  TLV_ASSIGN_OR_RETURN(const uint32_t in, values.value(op.inputs[0]));
  TLV_ASSIGN_OR_RETURN(const uint32_t out, values.value(op.output));
  TLV_ASSIGN_OR_RETURN(const uint32_t bias, define_bias(values, t, cout, who));
  if (t.weights.dtype == DType::kFloat32) {
    TLV_ASSIGN_OR_RETURN(
        const uint32_t filter,
        define_weights(values, t, dims_of(t.weights.shape), 0, cout, t.weights.data.data(), who));
    return values.subgraph().define_fully_connected(activation_min(act), activation_max(act), in,
                                                    filter, bias, out, who);
  }

  // int8: 1x1 convolution on [N,1,1,C] views.
  const size_t in4_dims[4] = {batch, 1, 1, cin};
  const size_t out4_dims[4] = {batch, 1, 1, cout};
  TLV_ASSIGN_OR_RETURN(const uint32_t in4, values.define_internal(t.input, in4_dims, who));
  TLV_ASSIGN_OR_RETURN(const uint32_t out4, values.define_internal(output, out4_dims, who));
  TLV_TRY(values.subgraph().define_reshape(in4_dims, in, in4, who));
  Dims wdims;
  wdims.rank = 4;
  wdims.d = {cout, 1, 1, cin};
  Conv2DSpec spec;
  TLV_ASSIGN_OR_RETURN(spec.filter,
                       define_weights(values, t, wdims, 0, cout, t.weights.data.data(), who));
  spec.group_input_channels = cin;
  spec.group_output_channels = cout;
  spec.output_min = activation_min(act);
  spec.output_max = activation_max(act);
  spec.input = in4;
  spec.bias = bias;
  spec.output = out4;
  TLV_TRY(values.subgraph().define_convolution_2d(spec, who));
  const Dims out_dims = dims_of(output.shape);
  return values.subgraph().define_reshape(out_dims.span(), out4, out, who);
}

}  // namespace tlvlink::xnn
