// Writes the int8 / mixed-precision graph. Every float-model activation has a native form (the
// precision of the op producing it) and, on demand, a twin in the other precision made by a
// Quantize or Dequantize inserted just before its first consumer that needs it. Graph inputs
// and outputs stay fp32.
//
// Names: a native tensor keeps its float-model name; an int8 twin is "<name>.q", a float twin
// "<name>.dq"; a graph output's float form always has the plain name (its int8 form "<name>.q").

#include <algorithm>
#include <string>

#include "quantizer/quantizer_internal.h"
#include "tlvlink/quant_math.h"

namespace tlvlink::quantize::quantizer_internal {
namespace {

// int8 sigmoid output: (0, 1) over the whole int8 range (XNNPACK accepts only this).
constexpr float kSigmoidScale = 1.0f / 256.0f;
constexpr int32_t kSigmoidZeroPoint = -128;

std::vector<int32_t> dims_of(const Shape& s) { return {s.dims.begin(), s.dims.begin() + s.rank}; }

std::span<const float> floats_of(const Tensor& t) {
  return {reinterpret_cast<const float*>(t.data.data()), t.data.size() / sizeof(float)};
}

OpParams with_activation(const Operator& op, Activation a) {
  OpParams p = op.params;
  if (auto* c = std::get_if<Conv2DParams>(&p)) c->activation = a;
  if (auto* f = std::get_if<FullyConnectedParams>(&p)) f->activation = a;
  if (auto* b = std::get_if<BinaryParams>(&p)) b->activation = a;
  return p;
}

bool in_range(float ratio, float lo, float hi) { return ratio >= lo && ratio < hi; }

class Emitter {
 public:
  Emitter(const Model& m, std::span<const TensorRange> ranges, const QuantizerOptions& o,
          const std::vector<OpPlan>& plan)
      : model_(m),
        g_(m.graph()),
        ranges_(ranges),
        opt_(o),
        plan_(plan),
        slots_(g_.tensors.size()) {}

  Result<QuantizedModel> run() {
    TLV_ENSURE(ranges_.size() == g_.tensors.size(), ErrorCode::kInvalidArgument,
               "%zu ranges for %zu tensors", ranges_.size(), g_.tensors.size());
    std::vector<int32_t> inputs, outputs;
    for (int32_t in : g_.inputs) {
      const Tensor& t = g_.tensor(in);
      TLV_ENSURE(t.dtype == DType::kFloat32, ErrorCode::kModelUnsupported,
                 "graph input '%.*s' is %s; the quantizer expects a float model",
                 static_cast<int>(t.name.size()), t.name.data(), dtype_name(t.dtype));
      inputs.push_back(slot(in).f = out_.builder.add_activation(std::string(t.name),
                                                                DType::kFloat32, dims_of(t.shape)));
    }
    out_.layers.resize(g_.operators.size());
    for (size_t i = 0; i < g_.operators.size(); ++i) TLV_TRY(emit(i));
    for (int32_t o : g_.outputs) outputs.push_back(float_of(o));
    out_.builder.set_inputs(inputs);
    out_.builder.set_outputs(outputs);
    out_.builder.metadata() = metadata_spec_from(model_.metadata());
    out_.builder.metadata().golden.clear();
    out_.builder.metadata().quantization_json = opt_.quantization_json;
    return std::move(out_);
  }

 private:
  struct Slot {
    int32_t f = kNoTensor, q = kNoTensor;  // float / int8 form in the new graph
    QuantSpec qspec;                       // parameters of the int8 form
    bool native_int8 = false;
  };
  Slot& slot(int32_t t) { return slots_[static_cast<size_t>(t)]; }
  std::string name(int32_t t) const { return std::string(g_.tensor(t).name); }
  bool is_output(int32_t t) const {
    return std::find(g_.outputs.begin(), g_.outputs.end(), t) != g_.outputs.end();
  }

  // The int8 parameters `t` has, or would get from its calibrated range.
  ActivationParams params_of(int32_t t) {
    const Slot& s = slot(t);
    if (s.q != kNoTensor) return {s.qspec, {}};
    const Tensor& tensor = g_.tensor(t);
    if (tensor.is_constant()) {  // Add/Mul operand: its own values give the range
      const std::span<const float> v = floats_of(tensor);
      const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
      TensorRange r;
      r.min = *lo;
      r.max = *hi;
      return activation_params(r, opt_.min_activation_range);
    }
    return activation_params(ranges_[static_cast<size_t>(t)], opt_.min_activation_range);
  }

  int32_t define_native(int32_t t, bool int8, const QuantSpec& spec = {}) {
    Slot& s = slot(t);
    const Tensor& tensor = g_.tensor(t);
    if (int8) {
      s.qspec = spec;
      s.native_int8 = true;
      return s.q = out_.builder.add_activation(name(t) + (is_output(t) ? ".q" : ""), DType::kInt8,
                                               dims_of(tensor.shape), spec);
    }
    return s.f = out_.builder.add_activation(name(t), DType::kFloat32, dims_of(tensor.shape));
  }

  // Precondition: params_of(t) succeeded.
  int32_t int8_of(int32_t t) {
    Slot& s = slot(t);
    if (s.q != kNoTensor) return s.q;
    const Tensor& tensor = g_.tensor(t);
    s.qspec = params_of(t).spec;
    if (tensor.is_constant()) {
      const std::span<const float> v = floats_of(tensor);
      std::vector<int8_t> data(v.size());
      for (size_t i = 0; i < v.size(); ++i)
        data[i] = quantize_value(v[i], s.qspec.scale[0], s.qspec.zero_point[0]);
      return s.q = out_.builder.add_constant<int8_t>(name(t), dims_of(tensor.shape), data, s.qspec);
    }
    const int32_t from = float_of(t);
    s.q = out_.builder.add_activation(name(t) + ".q", DType::kInt8, dims_of(tensor.shape), s.qspec);
    out_.builder.add_op(OpType::kQuantize, "quantize." + name(t), {from}, s.q);
    ++out_.conversions;
    return s.q;
  }

  int32_t float_of(int32_t t) {
    Slot& s = slot(t);
    if (s.f != kNoTensor) return s.f;
    const Tensor& tensor = g_.tensor(t);
    if (tensor.is_constant()) {
      return s.f = out_.builder.add_constant_bytes(name(t), DType::kFloat32, dims_of(tensor.shape),
                                                   tensor.data);
    }
    s.f = out_.builder.add_activation(name(t) + (is_output(t) ? "" : ".dq"), DType::kFloat32,
                                      dims_of(tensor.shape));
    out_.builder.add_op(OpType::kDequantize, "dequantize." + name(t), {s.q}, s.f);
    ++out_.conversions;
    return s.f;
  }

  // The float bias of operator i with its BiasOffset added (the model's own values without one).
  std::vector<float> corrected_bias(size_t i) {
    const Operator& op = g_.operators[i];
    const std::span<const float> b = floats_of(g_.tensor(op.inputs[2]));
    std::vector<float> out(b.begin(), b.end());
    for (const BiasOffset& o : opt_.bias_offsets) {
      if (o.op != op.name) continue;
      for (size_t c = 0; c < out.size() && c < o.delta.size(); ++c) out[c] += o.delta[c];
    }
    return out;
  }
  bool has_offset(const Operator& op) const {
    return std::any_of(opt_.bias_offsets.begin(), opt_.bias_offsets.end(),
                       [&](const BiasOffset& o) { return o.op == op.name; });
  }

  Status emit_float(size_t i, std::string reason) {
    const Operator& op = g_.operators[i];
    const bool corrected = has_offset(op);  // bias input 2 becomes a corrected copy
    std::vector<int32_t> in;
    for (size_t k = 0; k < op.input_count; ++k) {
      if (op.inputs[k] == kNoTensor) {
        in.push_back(kNoTensor);
      } else if (corrected && k == 2) {
        const Tensor& b = g_.tensor(op.inputs[2]);
        const std::vector<float> v = corrected_bias(i);
        in.push_back(out_.builder.add_constant_bytes(std::string(b.name), DType::kFloat32,
                                                     dims_of(b.shape),
                                                     std::as_bytes(std::span<const float>(v))));
      } else {
        in.push_back(float_of(op.inputs[k]));
      }
    }
    const int32_t y = define_native(plan_[i].output, false);
    out_.builder.add_op(op.type, std::string(op.name), in, y,
                        with_activation(op, plan_[i].activation));
    LayerDecision& d = out_.layers[i];
    d.precision = LayerPrecision::kFloat;
    d.reason = std::move(reason);
    ++out_.float_ops;
    return {};
  }

  void finish_int8(size_t i, const std::vector<int32_t>& in, const QuantSpec& out_spec) {
    const Operator& op = g_.operators[i];
    const int32_t y = define_native(plan_[i].output, true, out_spec);
    out_.builder.add_op(op.type, std::string(op.name), in, y,
                        with_activation(op, plan_[i].activation));
    ++out_.int8_ops;
  }

  // Parameters of activation `t` as operand `role`, or the reason they do not exist.
  bool operand(int32_t t, const char* role, ActivationParams& p, std::string& why) {
    p = params_of(t);
    if (p.failure.empty()) return true;
    why = strf("%s '%s': %s", role, name(t).c_str(), p.failure.c_str());
    return false;
  }

  Status emit_linear(size_t i) {
    const Operator& op = g_.operators[i];
    ActivationParams in, out;
    std::string why;
    if (!operand(op.inputs[0], "input", in, why) || !operand(plan_[i].output, "output", out, why))
      return emit_float(i, why);
    const Tensor& w = g_.tensor(op.inputs[1]);
    LinearRequest r;
    r.weights = floats_of(w);
    r.cout = w.shape[0];
    std::vector<float> bias;
    if (op.inputs[2] != kNoTensor) {
      bias = corrected_bias(i);
      r.bias = bias;
    }
    r.input_scale = in.spec.scale[0];
    r.output_scale = out.spec.scale[0];
    r.granularity = opt_.weights;
    r.max_bias_scale_raise = opt_.max_bias_scale_raise;
    LinearWeights lw = quantize_linear(r);
    if (!lw.failure.empty()) return emit_float(i, lw.failure);
    const bool per_channel = opt_.weights == WeightGranularity::kPerChannel;
    const int32_t x = int8_of(op.inputs[0]);
    const int32_t wt =
        out_.builder.add_constant<int8_t>(std::string(w.name), dims_of(w.shape), lw.values,
                                          per_channel ? QuantSpec::per_channel(lw.scales, 0)
                                                      : QuantSpec::per_tensor(lw.scales[0], 0));
    int32_t bt = kNoTensor;
    if (op.inputs[2] != kNoTensor) {
      const Tensor& b = g_.tensor(op.inputs[2]);
      bt = out_.builder.add_constant<int32_t>(std::string(b.name), dims_of(b.shape), lw.bias,
                                              per_channel
                                                  ? QuantSpec::per_channel(lw.bias_scales, 0)
                                                  : QuantSpec::per_tensor(lw.bias_scales[0], 0));
    }
    finish_int8(i, {x, wt, bt}, out.spec);
    LayerDecision& d = out_.layers[i];
    d.adjustments = std::move(lw.adjustments);
    d.weight_sqnr_db = lw.weight_sqnr_db;
    return {};
  }

  Status emit_binary(size_t i) {
    const Operator& op = g_.operators[i];
    ActivationParams a, b, out;
    std::string why;
    if (!operand(op.inputs[0], "input", a, why) || !operand(op.inputs[1], "input", b, why) ||
        !operand(plan_[i].output, "output", out, why))
      return emit_float(i, why);
    const float sa = a.spec.scale[0], sb = b.spec.scale[0], so = out.spec.scale[0];
    if (op.type == OpType::kAdd) {
      for (const float ratio : {sa / so, sb / so}) {
        if (!in_range(ratio, kAddRatioMin, kAddRatioMax))
          return emit_float(i,
                            strf("input/output scale ratio %.4g outside XNNPACK's int8 Add range "
                                 "[2^-10, 2^8)",
                                 static_cast<double>(ratio)));
      }
    } else if (const float ratio = sa * sb / so; !in_range(ratio, kMulRatioMin, kMulRatioMax)) {
      return emit_float(i, strf("product/output scale ratio %.4g outside XNNPACK's int8 Multiply "
                                "range [2^-16, 2^8)",
                                static_cast<double>(ratio)));
    }
    finish_int8(i, {int8_of(op.inputs[0]), int8_of(op.inputs[1])}, out.spec);
    return {};
  }

  Status emit_gap(size_t i) {
    const Operator& op = g_.operators[i];
    ActivationParams in, out;
    std::string why;
    if (!operand(op.inputs[0], "input", in, why) || !operand(plan_[i].output, "output", out, why))
      return emit_float(i, why);
    const float ratio = in.spec.scale[0] / out.spec.scale[0];
    if (!in_range(ratio, kGapRatioMin, kGapRatioMax))
      return emit_float(i, strf("input/output scale ratio %.4g outside XNNPACK's int8 "
                                "GlobalAveragePool range [2^-8, 2^8)",
                                static_cast<double>(ratio)));
    finish_int8(i, {int8_of(op.inputs[0])}, out.spec);
    return {};
  }

  Status emit_sigmoid(size_t i) {
    const Operator& op = g_.operators[i];
    ActivationParams in;
    std::string why;
    if (!operand(op.inputs[0], "input", in, why)) return emit_float(i, why);
    finish_int8(i, {int8_of(op.inputs[0])},
                QuantSpec::per_tensor(kSigmoidScale, kSigmoidZeroPoint));
    return {};
  }

  // Clamp, MaxPool2D, Pad, Reshape, ResizeBilinear: int8 when their input is natively int8 or
  // is a graph input (quantized once, as any int8 consumer of it would need), sharing its
  // parameters (no requantization); after an fp32 op they stay fp32.
  Status emit_pass_through(size_t i) {
    const Operator& op = g_.operators[i];
    const bool graph_input =
        std::find(g_.inputs.begin(), g_.inputs.end(), op.inputs[0]) != g_.inputs.end();
    if (!slot(op.inputs[0]).native_int8 && !graph_input)
      return emit_float(i, "input is fp32 (pass-through op follows its input)");
    ActivationParams p;
    std::string why;
    if (!operand(op.inputs[0], "input", p, why)) return emit_float(i, why);
    const QuantSpec spec = p.spec;  // the input's int8 parameters (existing or calibrated)
    if (op.type == OpType::kPad) {
      const float v = op.get<PadParams>().value;
      const double q = static_cast<double>(v / spec.scale[0]) + spec.zero_point[0];
      if (!(q >= kInt8Min - 0.5 && q <= kInt8Max + 0.5))
        return emit_float(
            i, strf("pad value %g is outside the input's int8 range", static_cast<double>(v)));
    }
    finish_int8(i, {int8_of(op.inputs[0])}, spec);
    return {};
  }

  Status emit(size_t i) {
    const Operator& op = g_.operators[i];
    const OpPlan& p = plan_[i];
    LayerDecision& d = out_.layers[i];
    d.op = std::string(op.name);
    d.type = op.type;
    if (op.type == OpType::kQuantize || op.type == OpType::kDequantize) {
      return Error::make(ErrorCode::kModelUnsupported,
                         "operator '%s' (%s): the model is already (partly) quantized",
                         d.op.c_str(), op_type_name(op.type));
    }
    if (p.fused_into >= 0) {
      const auto into = static_cast<size_t>(p.fused_into);
      d.fused_into = out_.layers[into].op;
      d.precision = out_.layers[into].precision;
      ++out_.fused_ops;
      return {};
    }
    if (p.keep_float) return emit_float(i, "kept fp32 by --keep-float");
    if (!has_int8_kernel(op.type))
      return emit_float(i, strf("no int8 kernel for %s in the runtime", op_type_name(op.type)));
    switch (op.type) {
      case OpType::kConv2D:
      case OpType::kFullyConnected: return emit_linear(i);
      case OpType::kAdd:
      case OpType::kMul: return emit_binary(i);
      case OpType::kGlobalAveragePool: return emit_gap(i);
      case OpType::kSigmoid: return emit_sigmoid(i);
      default: return emit_pass_through(i);
    }
  }

  const Model& model_;
  const Graph& g_;
  std::span<const TensorRange> ranges_;
  const QuantizerOptions& opt_;
  const std::vector<OpPlan>& plan_;
  std::vector<Slot> slots_;
  QuantizedModel out_;
};

}  // namespace

Result<QuantizedModel> emit_quantized(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options,
                                      const std::vector<OpPlan>& plan) {
  return Emitter(fp32, ranges, options, plan).run();
}

}  // namespace tlvlink::quantize::quantizer_internal
