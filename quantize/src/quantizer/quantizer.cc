// Calibration pass (reference executor, every activation observed) and quantize_model.

#include "tlvlink/quantize/quantizer.h"

#include <cmath>
#include <cstring>

#include "quantizer/quantizer_internal.h"
#include "tlvlink/executor.h"

namespace tlvlink::quantize {

Result<bool> SpanInputSource::next(std::vector<float>& input) {
  if (next_ >= frames_.size()) return false;
  input = frames_[next_++];
  return true;
}

const char* weight_granularity_name(WeightGranularity g) {
  return g == WeightGranularity::kPerChannel ? "per-channel" : "per-tensor";
}

Result<CalibrationStats> calibrate(const Model& model, InputSource& inputs,
                                   const CalibrationRunOptions& options) {
  const Graph& g = model.graph();
  TLV_ENSURE(!g.inputs.empty() && g.tensor(g.inputs[0]).dtype == DType::kFloat32,
             ErrorCode::kModelUnsupported, "calibration needs a float model (graph input 0 float)");
  ExecutorOptions eo;
  eo.expose_all_tensors = true;
  eo.check_outputs = false;  // observe() names the tensor that goes non-finite
  TLV_ASSIGN_OR_RETURN(auto exec, make_reference_executor(model, eo));
  for (size_t i = 1; i < g.inputs.size(); ++i)
    std::memset(exec->input(i).data(), 0, exec->input(i).size());
  CalibrationStats stats;
  stats.tensors.resize(g.tensors.size());
  std::vector<float> frame;
  for (;;) {
    TLV_ASSIGN_OR_RETURN(const bool more, inputs.next(frame));
    if (!more) break;
    const uint64_t n = stats.frames;
    std::span<std::byte> in = exec->input(0);
    TLV_ENSURE(frame.size() * sizeof(float) == in.size(), ErrorCode::kShapeMismatch,
               "calibration frame %llu has %zu floats, graph input 0 needs %zu",
               static_cast<unsigned long long>(n), frame.size(), in.size() / sizeof(float));
    std::memcpy(in.data(), frame.data(), in.size());
    if (Status s = exec->invoke(); !s.ok())
      return s.error().with_context("calibration frame %llu", static_cast<unsigned long long>(n));
    for (size_t t = 0; t < g.tensors.size(); ++t) {
      const Tensor& tensor = g.tensors[t];
      if (tensor.is_constant() || tensor.dtype != DType::kFloat32) continue;
      TLV_ASSIGN_OR_RETURN(std::span<const std::byte> bytes, exec->tensor(static_cast<int32_t>(t)));
      const std::span<const float> values{reinterpret_cast<const float*>(bytes.data()),
                                          bytes.size() / sizeof(float)};
      if (Status s = stats.tensors[t].observe(values, tensor.name, options.averaging_constant);
          !s.ok())
        return s.error().with_context("calibration frame %llu", static_cast<unsigned long long>(n));
    }
    ++stats.frames;
    if (options.on_frame) options.on_frame(stats.frames);
  }
  TLV_ENSURE(stats.frames > 0, ErrorCode::kInvalidArgument, "calibration needs at least one frame");
  return stats;
}

Result<CalibrationStats> calibrate(const Model& model, std::span<const std::vector<float>> inputs,
                                   const CalibrationRunOptions& options) {
  SpanInputSource source(inputs);
  return calibrate(model, source, options);
}

std::vector<TensorRange> select_ranges(const CalibrationStats& stats,
                                       const CalibrationOptions& options) {
  std::vector<TensorRange> ranges(stats.tensors.size());
  for (size_t t = 0; t < stats.tensors.size(); ++t) {
    const TensorObserver& obs = stats.tensors[t];
    if (!obs.observed()) continue;
    const Range r = choose_range(obs, options);
    ranges[t].min = r.lo;
    ranges[t].max = r.hi;
  }
  return ranges;
}

Result<QuantizedModel> quantize_model(const Model& fp32, std::span<const TensorRange> ranges,
                                      const QuantizerOptions& options) {
  const Graph& g = fp32.graph();
  TLV_ENSURE(ranges.size() == g.tensors.size(), ErrorCode::kInvalidArgument,
             "%zu ranges for %zu tensors", ranges.size(), g.tensors.size());
  TLV_ENSURE(options.max_bias_scale_raise >= 1.0, ErrorCode::kInvalidArgument,
             "max_bias_scale_raise %g must be >= 1", options.max_bias_scale_raise);
  for (const Operator& op : g.operators) {
    TLV_ENSURE(op.type != OpType::kQuantize && op.type != OpType::kDequantize,
               ErrorCode::kModelUnsupported,
               "operator '%.*s' (%s): the model is already (partly) quantized",
               static_cast<int>(op.name.size()), op.name.data(), op_type_name(op.type));
  }
  // Every activation needs a range: a missing one means calibration did not cover this model.
  for (const Operator& op : g.operators) {
    const TensorRange& r = ranges[static_cast<size_t>(op.output)];
    const Tensor& t = g.tensor(op.output);
    if (t.dtype != DType::kFloat32) continue;  // not reached for a float model (checked above)
    TLV_ENSURE(r.observed(), ErrorCode::kInvalidArgument, "tensor '%.*s' has no calibration range",
               static_cast<int>(t.name.size()), t.name.data());
  }
  for (const BiasOffset& o : options.bias_offsets) {
    const Operator* op = nullptr;
    for (const Operator& candidate : g.operators)
      if (candidate.name == o.op) op = &candidate;
    TLV_ENSURE(
        op != nullptr && (op->type == OpType::kConv2D || op->type == OpType::kFullyConnected) &&
            op->inputs[2] != kNoTensor,
        ErrorCode::kInvalidArgument,
        "bias offset for '%s': the model has no Conv2D / FullyConnected of that name with a bias",
        o.op.c_str());
    const size_t channels = g.tensor(op->inputs[2]).shape.elements();
    TLV_ENSURE(o.delta.size() == channels, ErrorCode::kInvalidArgument,
               "bias offset for '%s': %zu values for %zu output channels", o.op.c_str(),
               o.delta.size(), channels);
    for (float d : o.delta)
      TLV_ENSURE(std::isfinite(d), ErrorCode::kNonFiniteValue, "bias offset for '%s' is not finite",
                 o.op.c_str());
  }
  TLV_ASSIGN_OR_RETURN(auto plan, quantizer_internal::make_plan(g, options));
  TLV_ASSIGN_OR_RETURN(QuantizedModel q,
                       quantizer_internal::emit_quantized(fp32, ranges, options, plan));
  // The loader is the judge of a model file; a rejection here is a quantizer bug.
  auto check = Model::load(q.builder.finish());
  if (!check.ok())
    return check.error().with_context("the quantized model does not load (quantizer bug)");
  return q;
}

}  // namespace tlvlink::quantize
