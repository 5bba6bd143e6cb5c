#include "model/tiny_models.h"

namespace tlvlink::testing {

using quantize::ModelBuilder;
using quantize::QuantSpec;

TinyInt8Model::TinyInt8Model() {
  conv_weights.resize(4 * 3 * 3 * 3);
  for (size_t i = 0; i < conv_weights.size(); ++i) {
    conv_weights[i] = static_cast<int8_t>(static_cast<int>(i * 37 % 255) - 127);
  }
}

std::vector<std::byte> TinyInt8Model::build() const {
  ModelBuilder b;
  const int32_t x = b.add_activation("input", DType::kFloat32, {1, 8, 8, 3});
  const int32_t xq = b.add_activation("input_q", DType::kInt8, {1, 8, 8, 3},
                                      QuantSpec::per_tensor(input_scale, input_zero_point));
  const int32_t w =
      b.add_constant<int8_t>("conv.weight", {4, 3, 3, 3}, conv_weights,
                             QuantSpec::per_channel(conv_weight_scales, conv_weight_axis));
  std::vector<float> bias_scales;
  for (float s : conv_weight_scales)
    bias_scales.push_back(bias_scale_override ? bias_scale_override : input_scale * s);
  const int32_t bias = conv_has_bias
                           ? b.add_constant<int32_t>("conv.bias", {4}, conv_bias,
                                                     QuantSpec::per_channel(bias_scales, 0))
                           : kNoTensor;
  const int32_t y = b.add_activation("conv.out", DType::kInt8, conv_output_shape,
                                     QuantSpec::per_tensor(output_scale, conv_zero_point));
  const int32_t pooled = b.add_activation("pool.out", DType::kInt8, {1, 1, 1, 4},
                                          QuantSpec::per_tensor(output_scale, conv_zero_point));
  const int32_t flat = b.add_activation("flat", DType::kInt8, {1, 4},
                                        QuantSpec::per_tensor(output_scale, conv_zero_point));
  std::vector<int8_t> fc_w{10, -20, 30, -40, 50, -60, 70, -80};
  const int32_t fw =
      b.add_constant<int8_t>("fc.weight", {2, 4}, fc_w, QuantSpec::per_channel({0.01f, 0.02f}, 0));
  const int32_t fo =
      b.add_activation("fc.out", DType::kInt8, {1, 2}, QuantSpec::per_tensor(0.1f, 0));
  const int32_t out = b.add_activation("embedding", DType::kFloat32, {1, 2});
  b.add_op(OpType::kQuantize, "quantize_input", {x}, xq);
  b.add_op(OpType::kConv2D, "conv", {xq, w, bias}, y, conv);
  b.add_op(OpType::kGlobalAveragePool, "pool", {y}, pooled);
  b.add_op(OpType::kReshape, "flatten", {pooled}, flat);
  b.add_op(OpType::kFullyConnected, "fc", {flat, fw, kNoTensor}, fo);
  b.add_op(OpType::kDequantize, "dequantize_output", {fo}, out);
  b.set_inputs({x});
  b.set_outputs({out});
  b.metadata().name = "tiny";
  b.metadata().embedding_dim = 2;
  if (tweak) tweak(b);
  return b.finish();
}

}  // namespace tlvlink::testing
