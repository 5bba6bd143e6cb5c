#include "quantizer/quantizer_graphs.h"

#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/executor.h"

namespace tlvlink::quantizer_test {

using quantize::ModelBuilder;

std::vector<std::byte> conv_model(int32_t h, int32_t w, int32_t cin, int32_t cout, int32_t k,
                                  const std::vector<float>& weights, const std::vector<float>& bias,
                                  Activation act) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, h, w, cin});
  const int32_t wt = b.add_constant<float>("conv.w", {cout, k, k, cin}, weights);
  const int32_t bt = bias.empty() ? kNoTensor : b.add_constant<float>("conv.b", {cout}, bias);
  const int32_t y = b.add_activation("conv", DType::kFloat32, {1, h, w, cout});
  Conv2DParams p;
  p.kernel_h = p.kernel_w = k;
  p.pad_top = p.pad_left = (k - 1) / 2;
  p.pad_bottom = p.pad_right = k / 2;
  p.activation = act;
  b.add_op(OpType::kConv2D, "conv", {x, wt, bt}, y, p);
  b.set_inputs({x});
  b.set_outputs({y});
  b.metadata().name = "conv";
  return b.finish();
}

std::vector<std::byte> small_network(uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto floats = [&](size_t n, float scale) {
    std::uniform_real_distribution<float> d(-scale, scale);
    std::vector<float> v(n);
    for (float& f : v) f = d(rng);
    return v;
  };
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 8, 8, 3});
  auto conv = [&](const char* name, int32_t in, int32_t cin, int32_t cout, int32_t k,
                  int32_t stride, int32_t out_hw, Activation act) {
    const std::string n(name);
    const int32_t wt = b.add_constant<float>(n + ".w", {cout, k, k, cin},
                                             floats(static_cast<size_t>(cout * k * k * cin), 0.5f));
    const int32_t bt =
        b.add_constant<float>(n + ".b", {cout}, floats(static_cast<size_t>(cout), 0.1f));
    const int32_t y = b.add_activation(n, DType::kFloat32, {1, out_hw, out_hw, cout});
    Conv2DParams p;
    p.kernel_h = p.kernel_w = k;
    p.stride_h = p.stride_w = stride;
    p.pad_top = p.pad_left = p.pad_bottom = p.pad_right = k / 2;
    if (stride == 2 && k == 3) p.pad_bottom = p.pad_right = 0;
    p.activation = act;
    b.add_op(OpType::kConv2D, n, {in, wt, bt}, y, p);
    return y;
  };
  const int32_t c1 = conv("conv1", x, 3, 8, 3, 1, 8, Activation::kRelu6);
  const int32_t c2 = conv("conv2", c1, 8, 8, 1, 1, 8, Activation::kNone);
  const int32_t a = b.add_activation("add", DType::kFloat32, {1, 8, 8, 8});
  b.add_op(OpType::kAdd, "add", {c2, c1}, a, BinaryParams{});
  const int32_t c3 = conv("conv3", a, 8, 8, 3, 2, 4, Activation::kRelu);
  const int32_t g = b.add_activation("gap", DType::kFloat32, {1, 1, 1, 8});
  b.add_op(OpType::kGlobalAveragePool, "gap", {c3}, g);
  const int32_t r = b.add_activation("flat", DType::kFloat32, {1, 8});
  b.add_op(OpType::kReshape, "flat", {g}, r);
  const int32_t fw = b.add_constant<float>("fc.w", {16, 8}, floats(128, 0.5f));
  const int32_t out = b.add_activation("out", DType::kFloat32, {1, 16});
  b.add_op(OpType::kFullyConnected, "fc", {r, fw, kNoTensor}, out, FullyConnectedParams{});
  b.set_inputs({x});
  b.set_outputs({out});
  b.metadata().name = "small";
  b.metadata().embedding_dim = 16;
  return b.finish();
}

std::vector<std::vector<float>> random_frames(size_t count, size_t elements, float lo, float hi,
                                              uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> d(lo, hi);
  std::vector<std::vector<float>> frames(count, std::vector<float>(elements));
  for (auto& f : frames)
    for (float& v : f) v = d(rng);
  return frames;
}

std::unique_ptr<Quantized> quantize_for_test(const Model& fp32,
                                             const std::vector<std::vector<float>>& frames,
                                             const quantize::QuantizerOptions& options,
                                             quantize::CalibrationMethod method) {
  auto stats = quantize::calibrate(fp32, frames);
  if (!stats.ok()) {
    ADD_FAILURE() << "calibrate: " << stats.error().message();
    return nullptr;
  }
  quantize::CalibrationOptions c;
  c.method = method;
  auto q = quantize::quantize_model(fp32, quantize::select_ranges(*stats, c), options);
  if (!q.ok()) {
    ADD_FAILURE() << "quantize_model: " << q.error().message();
    return nullptr;
  }
  auto out = std::make_unique<Quantized>(Quantized{std::move(q).value(), nullptr});
  out->model = testing::load_model(out->q.builder.finish());
  if (out->model == nullptr) return nullptr;
  return out;
}

std::vector<float> run(const Model& model, const std::vector<float>& input) {
  auto exec = make_reference_executor(model);
  if (!exec.ok()) {
    ADD_FAILURE() << exec.error().message();
    return {};
  }
  std::memcpy((*exec)->input(0).data(), input.data(), (*exec)->input(0).size());
  if (Status s = (*exec)->invoke(); !s.ok()) {
    ADD_FAILURE() << s.error().message();
    return {};
  }
  const std::span<const std::byte> out = (*exec)->output(0);
  const auto* f = reinterpret_cast<const float*>(out.data());
  return std::vector<float>(f, f + out.size() / sizeof(float));
}

const quantize::LayerDecision* decision(const quantize::QuantizedModel& q, const std::string& op) {
  for (const quantize::LayerDecision& d : q.layers)
    if (d.op == op) return &d;
  ADD_FAILURE() << "no decision for " << op;
  return nullptr;
}

const Operator* producer_of(const Model& m, const std::string& tensor) {
  for (const Operator& op : m.graph().operators)
    if (m.graph().tensor(op.output).name == tensor) return &op;
  return nullptr;
}

int count_ops(const Model& m, OpType type) {
  int n = 0;
  for (const Operator& op : m.graph().operators) n += op.type == type ? 1 : 0;
  return n;
}

}  // namespace tlvlink::quantizer_test
