// Node labels for error messages and typed attribute access (a wrong attribute type is an
// error naming the node, never a silent default).

#include <cstdarg>
#include <cstdio>

#include "onnx/onnx_internal.h"

namespace tlvlink::quantize::onnx_internal {
namespace {

Error wrong_type(const onnx::NodeProto& node, const onnx::AttributeProto& a, const char* want) {
  return node_error(ErrorCode::kFormat, node, "attribute '%s' should be %s (type %d)",
                    a.name().c_str(), want, static_cast<int>(a.type()));
}

}  // namespace

std::string node_name(const onnx::NodeProto& node) {
  if (!node.name().empty()) return node.name();
  return node.output_size() > 0 ? node.output(0) : std::string("?");
}

std::string node_label(const onnx::NodeProto& node) {
  std::string label = node.op_type() + " node '";
  if (!node.name().empty()) return label + node.name() + "'";
  return label + (node.output_size() > 0 ? node.output(0) : std::string("?")) + "' (unnamed)";
}

Error node_error(ErrorCode code, const onnx::NodeProto& node, const char* format, ...) {
  char message[Error::kMaxErrorMessage + 1];
  va_list args;
  va_start(args, format);
  std::vsnprintf(message, sizeof message, format, args);
  va_end(args);
  return Error::make(code, "%s: %s", node_label(node).c_str(), message);
}

const onnx::AttributeProto* find_attribute(const onnx::NodeProto& node, std::string_view name) {
  for (const onnx::AttributeProto& a : node.attribute()) {
    if (a.name() == name) return &a;
  }
  return nullptr;
}

Result<int64_t> attr_int(const onnx::NodeProto& node, std::string_view name, int64_t fallback) {
  const onnx::AttributeProto* a = find_attribute(node, name);
  if (a == nullptr) return fallback;
  if (a->type() != onnx::AttributeProto_AttributeType_INT) return wrong_type(node, *a, "an int");
  return static_cast<int64_t>(a->i());
}

Result<float> attr_float(const onnx::NodeProto& node, std::string_view name, float fallback) {
  const onnx::AttributeProto* a = find_attribute(node, name);
  if (a == nullptr) return fallback;
  if (a->type() != onnx::AttributeProto_AttributeType_FLOAT) return wrong_type(node, *a, "a float");
  return a->f();
}

Result<std::vector<int64_t>> attr_ints(const onnx::NodeProto& node, std::string_view name) {
  const onnx::AttributeProto* a = find_attribute(node, name);
  if (a == nullptr) return std::vector<int64_t>{};
  if (a->type() != onnx::AttributeProto_AttributeType_INTS) return wrong_type(node, *a, "ints");
  return std::vector<int64_t>(a->ints().begin(), a->ints().end());
}

Result<std::string> attr_string(const onnx::NodeProto& node, std::string_view name,
                                std::string fallback) {
  const onnx::AttributeProto* a = find_attribute(node, name);
  if (a == nullptr) return fallback;
  if (a->type() != onnx::AttributeProto_AttributeType_STRING)
    return wrong_type(node, *a, "a string");
  return a->s();
}

}  // namespace tlvlink::quantize::onnx_internal
