#include "xnnpack/harness.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <gtest/gtest.h>

#include "tlvlink/quant_math.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::testing {

using quantize::ModelBuilder;
using quantize::QuantSpec;

int32_t TGraph::activation(std::string name, std::vector<int32_t> shape) {
  tensors.push_back({std::move(name), std::move(shape), TKind::kActivation, {}});
  return static_cast<int32_t>(tensors.size() - 1);
}

int32_t TGraph::constant(std::string name, std::vector<int32_t> shape, std::vector<float> data,
                         TKind kind) {
  tensors.push_back({std::move(name), std::move(shape), kind, std::move(data)});
  return static_cast<int32_t>(tensors.size() - 1);
}

int32_t TGraph::op(OpType type, std::string name, std::vector<int32_t> in,
                   std::vector<int32_t> out_shape, OpParams params) {
  const int32_t out = activation(name + ".out", std::move(out_shape));
  ops.push_back({type, std::move(name), std::move(in), out, params});
  return out;
}

namespace {

void add_ops_and_io(ModelBuilder& b, const TGraph& g) {
  for (const TOp& op : g.ops) b.add_op(op.type, op.name, op.inputs, op.output, op.params);
  b.set_inputs(g.inputs);
  b.set_outputs(g.outputs);
}

Activation* fused_activation(OpParams& params) {
  if (auto* c = std::get_if<Conv2DParams>(&params)) return &c->activation;
  if (auto* f = std::get_if<FullyConnectedParams>(&params)) return &f->activation;
  if (auto* a = std::get_if<BinaryParams>(&params)) return &a->activation;
  return nullptr;
}

// Smallest calibrated range and largest requantization multiplier the generated models use: the
// loader's limit is 256, XNNPACK's int8 add also needs input/output ratios above 2^-10.
constexpr float kMinRange = 1.0f / 32.0f;
constexpr float kMaxTestMultiplier = 64.0f;

bool passes_quantization_through(OpType t) {
  return t == OpType::kClamp || t == OpType::kMaxPool2D || t == OpType::kPad ||
         t == OpType::kReshape || t == OpType::kResizeBilinear;
}

std::vector<float> as_floats(const std::vector<std::byte>& bytes) {
  std::vector<float> v(bytes.size() / sizeof(float));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(float));
  return v;
}

}  // namespace

std::vector<std::byte> build_fp32(const TGraph& g) {
  ModelBuilder b;
  for (const TTensor& t : g.tensors) {
    const int32_t i = t.kind == TKind::kActivation
                          ? b.add_activation(t.name, DType::kFloat32, t.shape)
                          : b.add_constant<float>(t.name, t.shape, std::span<const float>(t.data));
    EXPECT_EQ(static_cast<size_t>(i) + 1, b.tensor_count());
  }
  add_ops_and_io(b, g);
  return b.finish();
}

TGraph magnitude_graph(const TGraph& graph) {
  TGraph g = graph;
  for (TTensor& t : g.tensors) {
    for (float& x : t.data) x = std::fabs(x);
  }
  for (TOp& op : g.ops) {
    if (Activation* a = fused_activation(op.params)) *a = Activation::kNone;
    if (op.type == OpType::kClamp) op.params = ClampParams{-1e30f, 1e30f};
  }
  return g;
}

double reduction_length(const TGraph& g) {
  double k = 0;
  for (const TOp& op : g.ops) {
    const TTensor& in = g.tensor(op.inputs[0]);
    switch (op.type) {
      case OpType::kConv2D: {
        const TTensor& w = g.tensor(op.inputs[1]);
        k += static_cast<double>(w.shape[1]) * w.shape[2] * w.shape[3];
        break;
      }
      case OpType::kFullyConnected: k += g.tensor(op.inputs[1]).shape[1]; break;
      case OpType::kGlobalAveragePool: k += static_cast<double>(in.shape[1]) * in.shape[2]; break;
      case OpType::kResizeBilinear: k += 4; break;
      default: k += 1; break;
    }
  }
  return std::max(k, 1.0);
}

std::vector<std::byte> build_int8(const TGraph& g, const std::vector<QParam>& quant) {
  // Weight quantization first: a bias needs its op's input scale and weight scales.
  std::vector<QuantizedWeights> weights(g.tensors.size());
  std::vector<std::vector<float>> bias_scales(g.tensors.size());
  std::vector<std::vector<int32_t>> bias_values(g.tensors.size());
  for (const TOp& op : g.ops) {
    if (op.type != OpType::kConv2D && op.type != OpType::kFullyConnected) continue;
    const TTensor& w = g.tensor(op.inputs[1]);
    QuantizedWeights& q = weights[static_cast<size_t>(op.inputs[1])];
    q = quantize_weights_per_channel(w.data, w.shape[0]);
    if (op.inputs.size() > 2 && op.inputs[2] != kNoTensor) {
      const size_t bi = static_cast<size_t>(op.inputs[2]);
      const float s_in = quant[static_cast<size_t>(op.inputs[0])].scale;
      for (float s : q.scales) bias_scales[bi].push_back(s_in * s);
      bias_values[bi] = quantize_bias(g.tensor(op.inputs[2]).data, s_in, q.scales);
    }
  }
  ModelBuilder b;
  for (size_t i = 0; i < g.tensors.size(); ++i) {
    const TTensor& t = g.tensors[i];
    const QParam q = quant[i];
    switch (t.kind) {
      case TKind::kActivation:
        b.add_activation(t.name, DType::kInt8, t.shape,
                         QuantSpec::per_tensor(q.scale, q.zero_point));
        break;
      case TKind::kWeights:
        b.add_constant<int8_t>(t.name, t.shape, std::span<const int8_t>(weights[i].values),
                               QuantSpec::per_channel(weights[i].scales, 0));
        break;
      case TKind::kBias:
        b.add_constant<int32_t>(t.name, t.shape, std::span<const int32_t>(bias_values[i]),
                                QuantSpec::per_channel(bias_scales[i], 0));
        break;
      case TKind::kConstant: {
        std::vector<int8_t> v(t.data.size());
        for (size_t k = 0; k < v.size(); ++k)
          v[k] = quantize_value(t.data[k], q.scale, q.zero_point);
        b.add_constant<int8_t>(t.name, t.shape, std::span<const int8_t>(v),
                               QuantSpec::per_tensor(q.scale, q.zero_point));
        break;
      }
    }
  }
  add_ops_and_io(b, g);
  return b.finish();
}

std::vector<QParam> calibrate(const TGraph& g, const Model& fp32_model,
                              const std::vector<std::vector<float>>& inputs, Rng& rng,
                              float range_lo, float range_hi) {
  std::vector<std::vector<std::byte>> raw;
  for (const auto& in : inputs) raw.push_back(to_bytes(in));
  const RunOutput out = run(fp32_model, ExecutorKind::kReference, raw);
  // Real ranges [lo, hi] (containing 0), scaled by a random factor.
  std::vector<float> lo(g.tensors.size(), 0.0f), hi(g.tensors.size(), 0.0f);
  for (size_t i = 0; i < g.tensors.size(); ++i) {
    const TTensor& t = g.tensors[i];
    if (t.kind == TKind::kWeights || t.kind == TKind::kBias) continue;
    const std::vector<float> v =
        t.kind == TKind::kConstant
            ? t.data
            : (i < out.tensors.size() ? as_floats(out.tensors[i]) : std::vector<float>{});
    for (float x : v) lo[i] = std::min(lo[i], x), hi[i] = std::max(hi[i], x);
    const float f = rng.uniform(range_lo, range_hi);
    lo[i] *= f, hi[i] *= f;
    // A quantizer floors degenerate ranges (quantization.md, edge case 1); the data here is O(1).
    if (hi[i] - lo[i] < kMinRange) hi[i] = lo[i] + kMinRange;
  }
  auto scale_of = [&](size_t i) { return (hi[i] - lo[i]) / 255.0f; };
  // Widens tensor i's range so its scale is at least `min_scale`.
  auto widen = [&](size_t i, float min_scale) {
    const float k = min_scale / scale_of(i);
    if (k > 1.0f) lo[i] *= k, hi[i] *= k;
  };
  for (const TOp& op : g.ops) {  // in order, so chains of pass-through ops inherit correctly
    const size_t o = static_cast<size_t>(op.output);
    const size_t a = static_cast<size_t>(op.inputs[0]);
    if (passes_quantization_through(op.type)) {
      lo[o] = lo[a], hi[o] = hi[a];
    } else if (op.type == OpType::kSigmoid) {
      lo[o] = 0.0f, hi[o] = 1.0f - 1.0f / 256.0f;  // scale 1/256, zero point -128
    } else if (op.type == OpType::kAdd) {
      const size_t b = static_cast<size_t>(op.inputs[1]);
      widen(o, std::max(scale_of(a), scale_of(b)) / kMaxTestMultiplier);
    } else if (op.type == OpType::kMul) {
      widen(o, scale_of(a) * scale_of(static_cast<size_t>(op.inputs[1])) / kMaxTestMultiplier);
    } else if (op.type == OpType::kGlobalAveragePool) {
      widen(o, scale_of(a) / kMaxTestMultiplier);
    } else if (op.type == OpType::kConv2D || op.type == OpType::kFullyConnected) {
      const TTensor& w = g.tensor(op.inputs[1]);
      const QuantizedWeights qw = quantize_weights_per_channel(w.data, w.shape[0]);
      const float max_w = *std::max_element(qw.scales.begin(), qw.scales.end());
      widen(o, scale_of(a) * max_w / kMaxTestMultiplier);
    }
  }
  std::vector<QParam> q(g.tensors.size());
  for (size_t i = 0; i < q.size(); ++i) {
    q[i].scale = scale_of(i);
    q[i].zero_point = std::clamp(round_half_even(-128.0f - lo[i] / q[i].scale), kInt8Min, kInt8Max);
  }
  for (const TOp& op : g.ops) {
    if (op.type == OpType::kSigmoid)
      q[static_cast<size_t>(op.output)] = QParam{1.0f / 256.0f, -128};
  }
  return q;
}

RunOutput run(const Model& model, ExecutorKind kind,
              const std::vector<std::vector<std::byte>>& inputs, int threads) {
  RunOutput out;
  ExecutorOptions options;
  options.threads = threads;
  options.expose_all_tensors = true;
  auto exec = make_executor(model, kind, options);
  if (!exec.ok()) {
    ADD_FAILURE() << executor_kind_name(kind) << ": " << exec.error().message();
    return out;
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    std::span<std::byte> dst = (*exec)->input(i);
    EXPECT_EQ(dst.size(), inputs[i].size());
    std::memcpy(dst.data(), inputs[i].data(), std::min(dst.size(), inputs[i].size()));
  }
  if (Status s = (*exec)->invoke(); !s.ok()) {
    ADD_FAILURE() << executor_kind_name(kind) << " invoke: " << s.error().message();
    return out;
  }
  const size_t n = model.graph().tensors.size();
  out.tensors.resize(n);
  for (size_t i = 0; i < n; ++i) {
    auto t = (*exec)->tensor(static_cast<int32_t>(i));
    if (t.ok()) out.tensors[i].assign(t->begin(), t->end());
  }
  return out;
}

std::vector<std::byte> to_bytes(const std::vector<float>& v) {
  std::vector<std::byte> b(v.size() * sizeof(float));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

std::vector<std::byte> to_bytes(const std::vector<int8_t>& v) {
  std::vector<std::byte> b(v.size());
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

std::vector<std::byte> quantize_input(const std::vector<float>& v, QParam q) {
  std::vector<int8_t> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = quantize_value(v[i], q.scale, q.zero_point);
  return to_bytes(out);
}

std::string Agreement::summary() const {
  std::ostringstream s;
  s << "int8: " << int8_elements << " elements, "
    << (int8_elements ? 100.0 * static_cast<double>(int8_exact) / static_cast<double>(int8_elements)
                      : 100.0)
    << "% exact, max diff " << int8_max_diff << " LSB (propagated " << int8_max_propagated_diff
    << " LSB); fp32: " << float_elements << " elements, max |diff|/allowed " << float_max_ratio;
  return s.str();
}

void compare_int8(const Model& model, const RunOutput& ref, const RunOutput& xnn, Agreement& agg) {
  const Graph& g = model.graph();
  if (ref.tensors.size() != g.tensors.size() || xnn.tensors.size() != g.tensors.size()) return;
  std::vector<bool> differs(g.tensors.size(), false);
  for (const Operator& op : g.operators) {
    bool inputs_agree = true;
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] != kNoTensor && differs[static_cast<size_t>(op.inputs[k])])
        inputs_agree = false;
    }
    const size_t o = static_cast<size_t>(op.output);
    if (g.tensors[o].dtype != DType::kInt8) continue;
    const auto& r = ref.tensors[o];
    const auto& x = xnn.tensors[o];
    ASSERT_EQ(r.size(), x.size()) << op.name;
    int max_diff = 0;
    size_t worst = 0;
    for (size_t i = 0; i < r.size(); ++i) {
      const int d = std::abs(static_cast<int>(static_cast<int8_t>(r[i])) -
                             static_cast<int>(static_cast<int8_t>(x[i])));
      if (d == 0) ++agg.int8_exact;
      if (d > max_diff) max_diff = d, worst = i;
    }
    agg.int8_elements += r.size();
    differs[o] = max_diff > 0;
    if (inputs_agree) {
      agg.int8_max_diff = std::max(agg.int8_max_diff, max_diff);
      EXPECT_LE(max_diff, kInt8Tolerance)
          << "operator '" << op.name << "' (" << op_type_name(op.type) << ") element " << worst
          << ": reference " << static_cast<int>(static_cast<int8_t>(r[worst])) << ", xnnpack "
          << static_cast<int>(static_cast<int8_t>(x[worst]));
    } else {
      agg.int8_max_propagated_diff = std::max(agg.int8_max_propagated_diff, max_diff);
    }
  }
}

void compare_fp32(const Model& model, const RunOutput& ref, const RunOutput& xnn,
                  const RunOutput& magnitude, double k, Agreement& agg) {
  const Graph& g = model.graph();
  if (ref.tensors.empty() || xnn.tensors.empty() || magnitude.tensors.empty()) return;
  for (int32_t t : g.outputs) {
    const size_t o = static_cast<size_t>(t);
    const std::vector<float> r = as_floats(ref.tensors[o]);
    const std::vector<float> x = as_floats(xnn.tensors[o]);
    const std::vector<float> m = as_floats(magnitude.tensors[o]);
    ASSERT_EQ(r.size(), x.size());
    ASSERT_EQ(r.size(), m.size());
    for (size_t i = 0; i < r.size(); ++i) {
      // The tiny absolute floor only matters when M == 0 (all-zero data): results must be 0.
      const double allowed =
          kFloatRelTolerance * std::sqrt(k) * std::fabs(static_cast<double>(m[i])) + 1e-30;
      const double diff = std::fabs(static_cast<double>(r[i]) - static_cast<double>(x[i]));
      agg.float_max_ratio = std::max(agg.float_max_ratio, diff / allowed);
      if (!(diff <= allowed)) {
        ADD_FAILURE() << "output '" << g.tensor(t).name << "' element " << i << ": reference "
                      << r[i] << ", xnnpack " << x[i] << ", allowed " << allowed << " (K=" << k
                      << ", M=" << m[i] << ")";
        return;
      }
    }
    agg.float_elements += r.size();
  }
}

void check_graph(const TGraph& graph, Rng& rng, Agreement& agg, float in_range) {
  std::vector<std::vector<float>> inputs;
  std::vector<std::vector<std::byte>> raw, raw_abs;
  for (int32_t t : graph.inputs) {
    size_t n = 1;
    for (int32_t d : graph.tensor(t).shape) n *= static_cast<size_t>(d);
    inputs.push_back(rng.floats(n, -in_range, in_range));
    raw.push_back(to_bytes(inputs.back()));
    std::vector<float> a = inputs.back();
    for (float& x : a) x = std::fabs(x);
    raw_abs.push_back(to_bytes(a));
  }
  {
    auto fp32 = load_model(build_fp32(graph));
    auto mag = load_model(build_fp32(magnitude_graph(graph)));
    ASSERT_NE(fp32, nullptr);
    ASSERT_NE(mag, nullptr);
    const RunOutput ref = run(*fp32, ExecutorKind::kReference, raw);
    const RunOutput xnn = run(*fp32, ExecutorKind::kXnnpack, raw);
    const RunOutput m = run(*mag, ExecutorKind::kReference, raw_abs);
    compare_fp32(*fp32, ref, xnn, m, reduction_length(graph), agg);
  }
  auto fp32 = load_model(build_fp32(graph));
  ASSERT_NE(fp32, nullptr);
  const std::vector<QParam> q = calibrate(graph, *fp32, inputs, rng);
  auto int8 = load_model(build_int8(graph, q));
  ASSERT_NE(int8, nullptr);
  std::vector<std::vector<std::byte>> qin;
  for (size_t i = 0; i < inputs.size(); ++i) {
    qin.push_back(quantize_input(inputs[i], q[static_cast<size_t>(graph.inputs[i])]));
  }
  const RunOutput ref = run(*int8, ExecutorKind::kReference, qin);
  const RunOutput xnn = run(*int8, ExecutorKind::kXnnpack, qin);
  compare_int8(*int8, ref, xnn, agg);
}

}  // namespace tlvlink::testing
