// The importer's graph walk: initializers, the one input, every node in order (constant folding
// or a converter), the outputs.

#include <limits>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

struct ConverterEntry {
  std::string_view op_type;
  Converter convert;
};
constexpr ConverterEntry kConverters[] = {
    {"Conv", convert_conv},
    {"Gemm", convert_gemm},
    {"MatMul", convert_matmul},
    {"BatchNormalization", convert_batch_norm},
    {"Relu", convert_relu},
    {"Clip", convert_clip},
    {"Sigmoid", convert_sigmoid},
    {"Add", convert_binary},
    {"Sub", convert_binary},
    {"Mul", convert_binary},
    {"Div", convert_binary},
    {"GlobalAveragePool", convert_global_average_pool},
    {"ReduceMean", convert_reduce_mean},
    {"MaxPool", convert_max_pool},
    {"Flatten", convert_flatten},
    {"Reshape", convert_reshape},
    {"Squeeze", convert_squeeze},
    {"Unsqueeze", convert_squeeze},
    {"Pad", convert_pad},
    {"Identity", convert_identity},
    {"Dropout", convert_identity},
};

bool is_float_tensor(const onnx::TypeProto& type) {
  return type.has_tensor_type() &&
         type.tensor_type().elem_type() == onnx::TensorProto_DataType_FLOAT;
}

}  // namespace

Converter find_converter(std::string_view op_type) {
  for (const ConverterEntry& e : kConverters) {
    if (e.op_type == op_type) return e.convert;
  }
  return nullptr;
}

Importer::Importer(const onnx::GraphProto& graph, int64_t opset) : graph_(graph), opset_(opset) {}

Status Importer::run() {
  for (const onnx::NodeProto& node : graph_.node()) {
    for (const std::string& in : node.input()) {
      if (!in.empty()) ++readers_[in];
    }
  }
  for (const onnx::ValueInfoProto& out : graph_.output()) ++readers_[out.name()];

  TLV_ENSURE(graph_.sparse_initializer_size() == 0, ErrorCode::kModelUnsupported,
             "the graph has sparse initializers, which tlvlink convert does not read");
  for (const onnx::TensorProto& t : graph_.initializer()) {
    TLV_ASSIGN_OR_RETURN(Constant c, read_tensor(t, "initializer '" + t.name() + "'"));
    bind_constant(t.name(), std::move(c));
  }
  // Older exporters list the initializers among the inputs too; the frame is the one left.
  const onnx::ValueInfoProto* input = nullptr;
  int inputs = 0;
  for (const onnx::ValueInfoProto& in : graph_.input()) {
    if (!is_constant(in.name())) {
      ++inputs;
      input = &in;
    }
  }
  TLV_ENSURE(inputs == 1, ErrorCode::kModelUnsupported,
             "the graph has %d inputs besides its initializers; tlvlink models take one frame",
             inputs);
  TLV_TRY(bind_input(*input));
  for (const onnx::NodeProto& node : graph_.node()) TLV_TRY(convert_node(node));
  TLV_ENSURE(graph_.output_size() >= 1, ErrorCode::kFormat, "the graph has no outputs");
  for (const onnx::ValueInfoProto& out : graph_.output()) TLV_TRY(bind_output(out));
  return {};
}

Status Importer::bind_input(const onnx::ValueInfoProto& input) {
  const char* name = input.name().c_str();
  TLV_ENSURE(is_float_tensor(input.type()), ErrorCode::kModelUnsupported,
             "input '%s' is not a float32 tensor; tlvlink convert imports float models", name);
  const onnx::TensorShapeProto& shape = input.type().tensor_type().shape();
  TLV_ENSURE(
      input.type().tensor_type().has_shape() && shape.dim_size() == 4, ErrorCode::kModelUnsupported,
      "input '%s' has rank %d; tlvlink models take an image [N, C, H, W]", name, shape.dim_size());
  std::vector<int64_t> dims(4);
  for (int k = 0; k < 4; ++k) {
    const onnx::TensorShapeProto_Dimension& d = shape.dim(k);
    if (k == 0) {
      // A symbolic batch ('N', 'batch') is read as 1.
      dims[0] = d.has_dim_value() ? d.dim_value() : 1;
      TLV_ENSURE(dims[0] == 1, ErrorCode::kModelUnsupported,
                 "input '%s' has batch %lld; tlvlink runs one frame at a time (export with "
                 "batch 1 or a symbolic batch)",
                 name, static_cast<long long>(dims[0]));
      continue;
    }
    TLV_ENSURE(d.has_dim_value(), ErrorCode::kModelUnsupported,
               "input '%s' dimension %d is dynamic ('%s'); tlvlink needs a fixed input size: "
               "export with fixed channels, height and width",
               name, k, d.dim_param().c_str());
    dims[static_cast<size_t>(k)] = d.dim_value();
    TLV_ENSURE(d.dim_value() >= 1 && d.dim_value() <= 65536, ErrorCode::kModelUnsupported,
               "input '%s' dimension %d is %lld", name, k, static_cast<long long>(d.dim_value()));
  }
  TLV_ENSURE(dims[1] == 1 || dims[1] == 3, ErrorCode::kModelUnsupported,
             "input '%s' %s has %lld channels; tlvlink frames have 1 (gray) or 3 (colour)", name,
             dims_string(dims).c_str(), static_cast<long long>(dims[1]));
  input_ = static_cast<int32_t>(values_.size());
  values_.push_back(Value{input.name(), dims, Layout::kNhwc, {}, -1, readers_[input.name()]});
  names_[input.name()] = Binding{input_, nullptr};
  return {};
}

Status Importer::convert_node(const onnx::NodeProto& node) {
  const std::string& op = node.op_type();
  if (!node.domain().empty() && node.domain() != "ai.onnx") {
    return Error::make(ErrorCode::kModelUnsupported,
                       "unsupported op type '%s' of domain '%s' (%s); tlvlink convert reads the "
                       "default ONNX domain",
                       op.c_str(), node.domain().c_str(), node_label(node).c_str());
  }
  bool all_constant = true;
  std::string first_activation;
  for (const std::string& in : node.input()) {
    if (in.empty()) continue;
    auto it = names_.find(in);
    if (it == names_.end()) {
      return node_error(ErrorCode::kFormat, node,
                        "reads '%s', which no earlier node or initializer defines (a truncated "
                        "file or a graph out of topological order)",
                        in.c_str());
    }
    if (it->second.value >= 0) {
      all_constant = false;
      if (first_activation.empty()) first_activation = in;
    }
  }
  for (const std::string& out : node.output()) {
    TLV_ENSURE(out.empty() || names_.find(out) == names_.end(), ErrorCode::kFormat,
               "%s writes '%s', which is already defined", node_label(node).c_str(), out.c_str());
  }
  TLV_ENSURE(node.output_size() >= 1 && !node.output(0).empty(), ErrorCode::kFormat,
             "%s has no output", node_label(node).c_str());

  if (const_evaluable(op) && (all_constant || op == "Shape")) {
    TLV_ASSIGN_OR_RETURN(Constant c, evaluate_constant(*this, node));
    bind_constant(node.output(0), std::move(c));
  } else if (Converter convert = find_converter(op); convert != nullptr) {
    TLV_TRY(convert(*this, node));
  } else if (const_evaluable(op)) {
    return node_error(ErrorCode::kModelUnsupported, node,
                      "is supported on constants only (shape arithmetic), here it reads the "
                      "activation '%s'",
                      first_activation.c_str());
  } else {
    return Error::make(ErrorCode::kModelUnsupported,
                       "unsupported op type '%s' (%s, opset %lld); quantize/README.md lists "
                       "the ops tlvlink convert supports",
                       op.c_str(), node_label(node).c_str(), static_cast<long long>(opset_));
  }
  // Secondary outputs (MaxPool indices, BatchNorm statistics, Dropout mask) are not computed.
  for (int k = 1; k < node.output_size(); ++k) {
    const std::string& out = node.output(k);
    if (out.empty() || names_.count(out) != 0) continue;
    TLV_ENSURE(readers_[out] == 0, ErrorCode::kModelUnsupported,
               "%s: output %d ('%s') is used, but tlvlink computes only output 0",
               node_label(node).c_str(), k, out.c_str());
  }
  return {};
}

Status Importer::bind_output(const onnx::ValueInfoProto& output) {
  const char* name = output.name().c_str();
  auto it = names_.find(output.name());
  TLV_ENSURE(it != names_.end(), ErrorCode::kFormat, "graph output '%s' is not computed", name);
  TLV_ENSURE(it->second.value >= 0, ErrorCode::kModelUnsupported,
             "graph output '%s' is a constant; tlvlink outputs are computed from the frame", name);
  const Value& v = value(it->second.value);
  TLV_ENSURE(v.producer >= 0, ErrorCode::kModelUnsupported, "graph output '%s' is the input itself",
             name);
  TLV_ENSURE(v.layout != Layout::kPermuted, ErrorCode::kModelUnsupported,
             "graph output '%s' is a flattened NCHW feature map, which tlvlink holds in NHWC "
             "order; add a Gemm/Linear after the flatten or a GlobalAveragePool before it",
             name);
  TLV_ENSURE(!output.type().has_tensor_type() || is_float_tensor(output.type()),
             ErrorCode::kModelUnsupported, "graph output '%s' is not float32", name);
  // A declared static shape must match what the importer computed (batch may be symbolic).
  const onnx::TensorShapeProto& declared = output.type().tensor_type().shape();
  if (output.type().tensor_type().has_shape()) {
    bool match = declared.dim_size() == static_cast<int>(v.shape.size());
    for (int k = 0; match && k < declared.dim_size(); ++k) {
      const auto& d = declared.dim(k);
      match = k == 0 || !d.has_dim_value() || d.dim_value() == v.shape[static_cast<size_t>(k)];
    }
    TLV_ENSURE(match, ErrorCode::kModelInvalidOperator,
               "graph output '%s' is declared with another shape than the computed %s", name,
               dims_string(v.shape).c_str());
  }
  outputs_.push_back(it->second.value);
  return {};
}

bool Importer::has_input(const onnx::NodeProto& node, int k) const {
  return k < node.input_size() && !node.input(k).empty();
}

bool Importer::is_constant(const std::string& name) const {
  auto it = names_.find(name);
  return it != names_.end() && it->second.constant != nullptr;
}

Result<int32_t> Importer::activation_input(const onnx::NodeProto& node, int k) const {
  if (!has_input(node, k)) return node_error(ErrorCode::kFormat, node, "input %d is missing", k);
  const Binding& b = names_.at(node.input(k));
  if (b.value < 0) {
    return node_error(ErrorCode::kModelUnsupported, node,
                      "input %d ('%s') is a constant; tlvlink needs an activation here", k,
                      node.input(k).c_str());
  }
  return b.value;
}

Result<const Constant*> Importer::constant_input(const onnx::NodeProto& node, int k) const {
  if (!has_input(node, k)) return node_error(ErrorCode::kFormat, node, "input %d is missing", k);
  const Binding& b = names_.at(node.input(k));
  if (b.constant == nullptr) {
    return node_error(ErrorCode::kModelUnsupported, node,
                      "input %d ('%s') must be a constant (an initializer or Constant node), "
                      "not a computed tensor",
                      k, node.input(k).c_str());
  }
  return b.constant;
}

Result<int32_t> Importer::add_node(Node node, const std::string& output_name,
                                   std::vector<int64_t> shape, Layout layout,
                                   std::vector<int64_t> perm) {
  for (int64_t d : shape) {
    TLV_ENSURE(d >= 1 && d <= std::numeric_limits<int32_t>::max(), ErrorCode::kModelUnsupported,
               "%s output '%s' would have shape %s (empty or too large)", node.name.c_str(),
               output_name.c_str(), dims_string(shape).c_str());
  }
  TLV_ENSURE(element_count(shape) > 0, ErrorCode::kModelUnsupported,
             "%s output '%s' %s is too large", node.name.c_str(), output_name.c_str(),
             dims_string(shape).c_str());
  const auto n = static_cast<int32_t>(nodes_.size());
  const auto v = static_cast<int32_t>(values_.size());
  values_.push_back(
      Value{output_name, std::move(shape), layout, std::move(perm), n, readers_[output_name]});
  node.output = v;
  nodes_.push_back(std::move(node));
  names_[output_name] = Binding{v, nullptr};
  return n;
}

void Importer::bind_constant(const std::string& name, Constant c) {
  constants_.push_back(std::move(c));
  names_[name] = Binding{-1, &constants_.back()};
}

void Importer::alias(const std::string& name, int32_t v) {
  names_[name] = Binding{v, nullptr};
  Value& x = value(v);
  x.uses += readers_[name] - 1;
  if (x.producer >= 0) x.name = name;  // the graph input keeps its own name
}

Node* Importer::sole_producer(int32_t v) {
  const Value& x = value(v);
  if (x.producer < 0 || x.uses != 1) return nullptr;
  Node& n = node(x.producer);
  return n.removed ? nullptr : &n;
}

}  // namespace tlvlink::quantize::onnx_internal
