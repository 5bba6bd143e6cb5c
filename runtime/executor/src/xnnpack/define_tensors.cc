#include "xnnpack/define_tensors.h"

#include <cstring>

namespace tlvlink::xnn {

Dims dims_of(const Shape& shape) {
  Dims dims;
  dims.rank = shape.rank;
  for (size_t i = 0; i < shape.rank; ++i) dims.d[i] = static_cast<size_t>(shape[i]);
  return dims;
}

NodeRef tensor_ref(const Graph& graph, int32_t tensor) {
  return NodeRef{"tensor", graph.tensor(tensor).name, tensor};
}

NodeRef operator_ref(const Graph& graph, int32_t op) {
  return NodeRef{"operator", graph.operators[static_cast<size_t>(op)].name, op};
}

ValueTable::ValueTable(const Graph& graph, Subgraph& subgraph, OwnedMemory& memory,
                       std::span<const ExternalFlags> flags)
    : graph_(graph),
      subgraph_(subgraph),
      memory_(memory),
      flags_(flags),
      ids_(graph.tensors.size(), kInvalidValueId) {}

Result<ValueDesc> ValueTable::activation_desc(int32_t tensor, const Dims& dims) {
  const Tensor& t = graph_.tensor(tensor);
  ValueDesc desc;
  desc.dims = dims.span();
  switch (t.dtype) {
    case DType::kFloat32: desc.type = ValueType::kFloat32; break;
    case DType::kInt8:
      // Activations are per-tensor (validated); a per-channel int8 operand has no XNNPACK form.
      TLV_ENSURE(t.quant.quantized() && !t.quant.per_channel(), ErrorCode::kModelUnsupported,
                 "tensor '%.*s' (#%d): XNNPACK int8 activations need per-tensor quantization",
                 static_cast<int>(t.name.size()), t.name.data(), tensor);
      desc.type = ValueType::kQInt8;
      desc.scale = t.quant.scale[0];
      desc.zero_point = t.quant.zero_point[0];
      break;
    default:
      return Error::make(ErrorCode::kModelUnsupported,
                         "tensor '%.*s' (#%d): dtype %s is not an XNNPACK activation type",
                         static_cast<int>(t.name.size()), t.name.data(), tensor,
                         dtype_name(t.dtype));
  }
  return desc;
}

Result<uint32_t> ValueTable::value(int32_t tensor) {
  const size_t index = static_cast<size_t>(tensor);
  if (ids_[index] != kInvalidValueId) return ids_[index];
  const Tensor& t = graph_.tensor(tensor);
  const Dims dims = dims_of(t.shape);
  TLV_ASSIGN_OR_RETURN(ValueDesc desc, activation_desc(tensor, dims));
  if (t.is_constant()) {
    // A constant used as an ordinary operand (e.g. the second input of Add) is read at every
    // invoke; copy it so kernels can read kExtraBytes past its end.
    TLV_ASSIGN_OR_RETURN(std::span<std::byte> copy, memory_.allocate(t.data.size()));
    std::memcpy(copy.data(), t.data.data(), t.data.size());
    desc.data = copy.data();
  } else if (flags_[index].input || flags_[index].output) {
    desc.external_id = static_cast<uint32_t>(tensor);
    desc.external_input = flags_[index].input;
    desc.external_output = flags_[index].output;
  }
  TLV_ASSIGN_OR_RETURN(ids_[index], subgraph_.define_value(desc, tensor_ref(graph_, tensor)));
  return ids_[index];
}

Result<uint32_t> ValueTable::define_internal(const Tensor& like, std::span<const size_t> dims,
                                             const NodeRef& who) {
  ValueDesc desc;
  desc.dims = dims;
  if (like.dtype == DType::kInt8) {
    desc.type = ValueType::kQInt8;
    desc.scale = like.quant.scale[0];
    desc.zero_point = like.quant.zero_point[0];
  }
  return subgraph_.define_value(desc, who);
}

}  // namespace tlvlink::xnn
