#include <cstdio>

#include "model_internal.h"

namespace tlvlink::model_internal {

Label tensor_label(const Graph& graph, int32_t index) {
  Label l{};
  if (index >= 0 && static_cast<size_t>(index) < graph.tensors.size()) {
    const auto name = graph.tensor(index).name;
    std::snprintf(l.text, sizeof(l.text), "tensor %d '%.*s'", index,
                  static_cast<int>(name.size() > 80 ? 80 : name.size()), name.data());
  } else {
    std::snprintf(l.text, sizeof(l.text), "tensor %d", index);
  }
  return l;
}

Label op_label(const Graph& graph, size_t op_index) {
  Label l{};
  const Operator& op = graph.operators[op_index];
  std::snprintf(l.text, sizeof(l.text), "operator %zu %s '%.*s'", op_index, op_type_name(op.type),
                static_cast<int>(op.name.size() > 64 ? 64 : op.name.size()), op.name.data());
  return l;
}

Label shape_label(const Shape& shape) {
  Label l{};
  int pos = std::snprintf(l.text, sizeof(l.text), "[");
  for (size_t i = 0; i < shape.rank && pos < 100; ++i) {
    pos += std::snprintf(l.text + pos, sizeof(l.text) - static_cast<size_t>(pos), i ? ",%d" : "%d",
                         shape.dims[i]);
  }
  std::snprintf(l.text + pos, sizeof(l.text) - static_cast<size_t>(pos), "]");
  return l;
}

}  // namespace tlvlink::model_internal

namespace tlvlink::model_internal {

bool same_quantization(const Tensor& a, const Tensor& b) {
  if (a.quant.scale.size() != b.quant.scale.size() || a.quant.axis != b.quant.axis) return false;
  for (size_t i = 0; i < a.quant.scale.size(); ++i) {
    if (a.quant.scale[i] != b.quant.scale[i] || a.quant.zero_point[i] != b.quant.zero_point[i]) {
      return false;
    }
  }
  return true;
}

}  // namespace tlvlink::model_internal
