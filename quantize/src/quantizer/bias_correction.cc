// Empirical bias correction, layer by layer (bias_correction.h says what and why).

#include "tlvlink/quantize/bias_correction.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string_view>

#include "quantizer/quantizer_internal.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::quantize {
namespace {

// Conv2D / FullyConnected operators of the float model that have a bias, in graph order.
std::vector<size_t> correctable_ops_of(const Graph& g) {
  std::vector<size_t> out;
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    if ((op.type == OpType::kConv2D || op.type == OpType::kFullyConnected) &&
        op.inputs[2] != kNoTensor)
      out.push_back(i);
  }
  return out;
}

int32_t find_tensor(const Graph& g, std::string_view name) {
  for (size_t t = 0; t < g.tensors.size(); ++t)
    if (g.tensors[t].name == name) return static_cast<int32_t>(t);
  return kNoTensor;
}

Result<std::unique_ptr<Executor>> executor_for(const Model& m, ExecutorKind kind) {
  ExecutorOptions o;
  o.expose_all_tensors = true;
  auto e = make_executor(m, kind, o);
  // A build without XNNPACK still corrects, on the reference executor.
  if (!e.ok() && e.error().code() == ErrorCode::kModelUnsupported && kind == ExecutorKind::kXnnpack)
    return make_executor(m, ExecutorKind::kReference, o);
  return e;
}

// Where one corrected layer's output lives in both models, and how to read it.
struct Probe {
  int32_t float_tensor = kNoTensor, quant_tensor = kNoTensor;
  float lo = 0, hi = 0;  // the fused activation's range (values at its ends were clamped)
  bool int8 = false;
  float scale = 0;
  int32_t zero_point = 0;
  size_t channels = 0;
};

Result<Probe> probe_for(const Graph& f, const Graph& q, const Operator& op) {
  Probe p;
  const Operator* qop = nullptr;
  for (const Operator& candidate : q.operators)
    if (candidate.name == op.name) qop = &candidate;
  TLV_ENSURE(qop != nullptr, ErrorCode::kInvalidState,
             "bias correction: operator '%.*s' is missing from the quantized model",
             static_cast<int>(op.name.size()), op.name.data());
  p.quant_tensor = qop->output;
  const Tensor& qt = q.tensor(qop->output);
  std::string_view name = qt.name;
  // A graph output's int8 form is "<name>.q" (emit.cc); the float model calls it "<name>".
  if (qt.dtype == DType::kInt8 && name.size() > 2 && name.substr(name.size() - 2) == ".q" &&
      find_tensor(f, name) == kNoTensor)
    name.remove_suffix(2);
  p.float_tensor = find_tensor(f, name);
  TLV_ENSURE(p.float_tensor != kNoTensor, ErrorCode::kInvalidState,
             "bias correction: tensor '%.*s' of operator '%.*s' is missing from the float model",
             static_cast<int>(name.size()), name.data(), static_cast<int>(op.name.size()),
             op.name.data());
  const Activation a = quantizer_internal::activation_of(*qop);
  p.lo = activation_min(a);
  p.hi = activation_max(a);
  p.int8 = qt.dtype == DType::kInt8;
  if (p.int8) {
    p.scale = qt.quant.scale[0];
    p.zero_point = qt.quant.zero_point[0];
  }
  p.channels = static_cast<size_t>(qt.shape.dims[qt.shape.rank - 1]);
  return p;
}

// Sums of (q - f) per channel over the elements inside the activation range on both sides
// (half a step away from its ends, and off the int8 rails, where rounding is one-sided).
struct ShiftSums {
  std::vector<double> sum;
  std::vector<uint64_t> count;
};

void accumulate(const Probe& p, std::span<const std::byte> fb, std::span<const std::byte> qb,
                ShiftSums& s) {
  const size_t n = fb.size() / sizeof(float);
  const auto* f = reinterpret_cast<const float*>(fb.data());
  const double margin = p.int8 ? 0.5 * static_cast<double>(p.scale) : 0.0;
  const double lo = static_cast<double>(p.lo) + margin, hi = static_cast<double>(p.hi) - margin;
  for (size_t i = 0; i < n; ++i) {
    double qv;
    if (p.int8) {
      const auto raw = static_cast<int8_t>(qb[i]);
      if (raw == kInt8Min || raw == kInt8Max) continue;
      qv = static_cast<double>(dequantize_value(raw, p.scale, p.zero_point));
    } else {
      float v;
      std::memcpy(&v, qb.data() + i * sizeof(float), sizeof(float));
      qv = static_cast<double>(v);
    }
    const auto fv = static_cast<double>(f[i]);
    if (!(fv > lo && fv < hi && qv > lo && qv < hi)) continue;
    const size_t c = i % p.channels;
    s.sum[c] += qv - fv;
    ++s.count[c];
  }
}

void add_offset(std::vector<BiasOffset>& offsets, const std::string& op,
                const std::vector<float>& d) {
  for (BiasOffset& o : offsets) {
    if (o.op != op) continue;
    for (size_t c = 0; c < d.size(); ++c) o.delta[c] += d[c];
    return;
  }
  offsets.push_back({op, d});
}

}  // namespace

size_t correctable_layers(const Graph& graph) { return correctable_ops_of(graph).size(); }

Result<CorrectedModel> correct_biases(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options,
                                      std::span<const std::vector<float>> frames,
                                      const BiasCorrectionOptions& correction) {
  const Graph& g = fp32.graph();
  TLV_ENSURE(!frames.empty() && correction.max_frames >= 1, ErrorCode::kInvalidArgument,
             "bias correction needs at least one calibration frame");
  const size_t n = std::min(correction.max_frames, frames.size());
  const size_t input_floats = g.tensor(g.inputs[0]).bytes() / sizeof(float);
  for (size_t i = 0; i < n; ++i)
    TLV_ENSURE(frames[i].size() == input_floats, ErrorCode::kShapeMismatch,
               "bias correction frame %zu has %zu values; the model input has %zu", i,
               frames[i].size(), input_floats);
  TLV_ASSIGN_OR_RETURN(auto fx, executor_for(fp32, correction.executor));

  CorrectedModel out;
  out.frames = n;
  QuantizerOptions opt = options;
  const std::vector<size_t> ops = correctable_ops_of(g);
  for (size_t k = 0; k < ops.size(); ++k) {
    const Operator& op = g.operators[ops[k]];
    TLV_ASSIGN_OR_RETURN(QuantizedModel q, quantize_model(fp32, ranges, opt));
    TLV_ASSIGN_OR_RETURN(auto qm, Model::load(q.builder.finish()));
    TLV_ASSIGN_OR_RETURN(auto qx, executor_for(*qm, correction.executor));
    TLV_ASSIGN_OR_RETURN(Probe p, probe_for(g, qm->graph(), op));
    ShiftSums sums{std::vector<double>(p.channels, 0.0), std::vector<uint64_t>(p.channels, 0)};
    for (size_t i = 0; i < n; ++i) {
      for (Executor* e : {fx.get(), qx.get()}) {
        std::memcpy(e->input(0).data(), frames[i].data(), e->input(0).size());
        if (Status s = e->invoke(); !s.ok())
          return s.error().with_context("bias correction of '%.*s', frame %zu",
                                        static_cast<int>(op.name.size()), op.name.data(), i);
      }
      TLV_ASSIGN_OR_RETURN(auto fb, fx->tensor(p.float_tensor));
      TLV_ASSIGN_OR_RETURN(auto qb, qx->tensor(p.quant_tensor));
      accumulate(p, fb, qb, sums);
    }
    BiasCorrectionLayer layer;
    layer.op = std::string(op.name);
    layer.int8 = p.int8;
    layer.step = static_cast<double>(p.scale);
    layer.channels = p.channels;
    std::vector<float> delta(p.channels, 0.0f);
    double abs_sum = 0;
    for (size_t c = 0; c < p.channels; ++c) {
      if (sums.count[c] == 0) continue;
      const double shift = sums.sum[c] / static_cast<double>(sums.count[c]);
      delta[c] = static_cast<float>(-shift);
      abs_sum += std::fabs(shift);
      layer.max_abs_shift = std::max(layer.max_abs_shift, std::fabs(shift));
      ++layer.channels_measured;
    }
    if (layer.channels_measured > 0)
      layer.mean_abs_shift = abs_sum / static_cast<double>(layer.channels_measured);
    add_offset(opt.bias_offsets, layer.op, delta);
    out.layers.push_back(std::move(layer));
    if (correction.on_layer) correction.on_layer(k + 1, ops.size());
  }
  TLV_ASSIGN_OR_RETURN(out.model, quantize_model(fp32, ranges, opt));
  out.offsets = std::move(opt.bias_offsets);
  return out;
}

}  // namespace tlvlink::quantize
