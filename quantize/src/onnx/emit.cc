// IR -> .tlvm through ModelBuilder. Only what the outputs depend on is written: nodes folded
// away (removed) and dead branches are skipped.

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {

Result<std::vector<std::byte>> emit_model(const Importer& imp, const MetadataSpec& metadata,
                                          size_t& operators) {
  const std::deque<Value>& values = imp.values();
  const std::deque<Node>& nodes = imp.nodes();
  std::vector<bool> live_value(values.size(), false), live_node(nodes.size(), false);
  for (int32_t v : imp.outputs()) live_value[static_cast<size_t>(v)] = true;
  for (size_t n = nodes.size(); n-- > 0;) {
    const Node& node = nodes[n];
    if (node.removed || !live_value[static_cast<size_t>(node.output)]) continue;
    live_node[n] = true;
    for (const Operand& in : node.inputs) {
      if (in.value >= 0) live_value[static_cast<size_t>(in.value)] = true;
    }
  }

  ModelBuilder b;
  std::vector<int32_t> tensor(values.size(), kNoTensor);
  auto activation = [&](int32_t v) {
    int32_t& t = tensor[static_cast<size_t>(v)];
    if (t == kNoTensor) {
      const Value& value = values[static_cast<size_t>(v)];
      t = b.add_activation(value.name, DType::kFloat32, stored_shape(value));
    }
    return t;
  };
  const int32_t input = activation(imp.input());
  operators = 0;
  for (size_t n = 0; n < nodes.size(); ++n) {
    if (!live_node[n]) continue;
    const Node& node = nodes[n];
    std::vector<int32_t> inputs;
    for (const Operand& in : node.inputs) {
      const ConstOperand& c = in.constant;
      inputs.push_back(in.value >= 0 ? activation(in.value)
                                     : b.add_constant<float>(c.name, c.shape, c.data));
    }
    b.add_op(node.type, node.name, std::move(inputs), activation(node.output), node.params);
    ++operators;
  }
  std::vector<int32_t> outputs;
  for (int32_t v : imp.outputs()) outputs.push_back(activation(v));
  b.set_inputs({input});
  b.set_outputs(std::move(outputs));
  b.metadata() = metadata;
  return b.finish();
}

}  // namespace tlvlink::quantize::onnx_internal
