// Min/max calibration and golden outputs, both through the reference executor.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "quantizer/quantizer_internal.h"
#include "tlvlink/executor.h"
#include "tlvlink/quant_math.h"
#include "tlvlink/quantize/calibrate.h"

namespace tlvlink::quantize {

Result<std::vector<TensorRange>> collect_ranges(const Model& model,
                                                std::span<const std::vector<float>> inputs) {
  const Graph& g = model.graph();
  TLV_ENSURE(!inputs.empty(), ErrorCode::kInvalidArgument, "calibration needs at least one input");
  ExecutorOptions eo;
  eo.expose_all_tensors = true;
  TLV_ASSIGN_OR_RETURN(auto exec, make_reference_executor(model, eo));
  std::vector<TensorRange> ranges(g.tensors.size());
  for (size_t n = 0; n < inputs.size(); ++n) {
    std::span<std::byte> in = exec->input(0);
    TLV_ENSURE(inputs[n].size() * sizeof(float) == in.size(), ErrorCode::kShapeMismatch,
               "calibration input %zu has %zu floats, graph input 0 needs %zu", n, inputs[n].size(),
               in.size() / sizeof(float));
    std::memcpy(in.data(), inputs[n].data(), in.size());
    if (Status s = exec->invoke(); !s.ok())
      return s.error().with_context("calibration frame %zu", n);
    for (size_t t = 0; t < g.tensors.size(); ++t) {
      const Tensor& tensor = g.tensors[t];
      if (tensor.is_constant() || tensor.dtype != DType::kFloat32) continue;
      TLV_ASSIGN_OR_RETURN(std::span<const std::byte> bytes, exec->tensor(static_cast<int32_t>(t)));
      const auto* v = reinterpret_cast<const float*>(bytes.data());
      const size_t count = bytes.size() / sizeof(float);
      TensorRange& r = ranges[t];
      for (size_t i = 0; i < count; ++i) {
        r.min = std::min(r.min, v[i]);
        r.max = std::max(r.max, v[i]);
      }
    }
  }
  return ranges;
}

QuantSpec activation_quant(float min, float max, float min_range) {
  TensorRange r;
  r.min = min;
  r.max = max;
  // A range with no finite normal scale gives an empty spec (quantize_model reports why).
  return quantizer_internal::activation_params(r, min_range).spec;
}

Result<std::vector<std::byte>> run_reference(const Model& model, std::span<const std::byte> input) {
  TLV_ASSIGN_OR_RETURN(auto exec, make_reference_executor(model));
  std::span<std::byte> in = exec->input(0);
  TLV_ENSURE(input.size() == in.size(), ErrorCode::kShapeMismatch,
             "input has %zu bytes, graph input 0 needs %zu", input.size(), in.size());
  std::memcpy(in.data(), input.data(), in.size());
  TLV_TRY(exec->invoke());
  std::span<const std::byte> out = exec->output(0);
  return std::vector<std::byte>(out.begin(), out.end());
}

}  // namespace tlvlink::quantize
