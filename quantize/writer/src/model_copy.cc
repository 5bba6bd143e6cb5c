// rebuild_with_metadata: a loaded model back into a builder, index for index.

#include "tlvlink/quantize/model_copy.h"

#include <vector>

namespace tlvlink::quantize {
namespace {

QuantSpec quant_of(const QuantParams& q) {
  QuantSpec s;
  s.scale.assign(q.scale.begin(), q.scale.end());
  s.zero_point.assign(q.zero_point.begin(), q.zero_point.end());
  s.axis = q.axis;
  return s;
}

std::vector<int32_t> dims_of(const Shape& shape) {
  return {shape.dims.begin(), shape.dims.begin() + static_cast<std::ptrdiff_t>(shape.rank)};
}

}  // namespace

Result<ModelBuilder> rebuild_with_metadata(const Model& model, const MetadataSpec& metadata) {
  const Graph& g = model.graph();
  ModelBuilder b;
  for (size_t i = 0; i < g.tensors.size(); ++i) {
    const Tensor& t = g.tensors[i];
    int32_t index = 0;
    if (t.is_constant()) {
      TLV_ENSURE(t.data.size() == t.bytes(), ErrorCode::kModelInvalidTensor,
                 "rebuild: constant '%.*s' holds %zu bytes, its shape needs %zu",
                 static_cast<int>(t.name.size()), t.name.data(), t.data.size(), t.bytes());
      index = b.add_constant_bytes(std::string(t.name), t.dtype, dims_of(t.shape), t.data,
                                   quant_of(t.quant));
    } else {
      index = b.add_activation(std::string(t.name), t.dtype, dims_of(t.shape), quant_of(t.quant));
    }
    // The builder numbers tensors in insertion order; operators refer to these indices.
    TLV_ENSURE(static_cast<size_t>(index) == i, ErrorCode::kInvalidState,
               "rebuild: tensor %zu was given index %d", i, index);
  }
  for (const Operator& op : g.operators) {
    std::vector<int32_t> inputs(op.inputs.begin(),
                                op.inputs.begin() + static_cast<std::ptrdiff_t>(op.input_count));
    b.add_op(op.type, std::string(op.name), std::move(inputs), op.output, op.params);
  }
  b.set_inputs(g.inputs);
  b.set_outputs(g.outputs);
  b.metadata() = metadata;
  if (metadata.golden.empty()) {
    for (const GoldenPair& p : model.metadata().golden) {
      b.metadata().golden.emplace_back(std::vector<std::byte>(p.input.begin(), p.input.end()),
                                       std::vector<std::byte>(p.output.begin(), p.output.end()));
    }
  }
  return b;
}

Result<std::vector<std::byte>> model_with_metadata(const Model& model,
                                                   const MetadataSpec& metadata) {
  TLV_ASSIGN_OR_RETURN(ModelBuilder builder, rebuild_with_metadata(model, metadata));
  std::vector<std::byte> bytes = builder.finish();
  auto check = Model::load(bytes);
  if (!check.ok())
    return check.error().with_context("the copy with the new metadata does not load");
  return bytes;
}

}  // namespace tlvlink::quantize
