#pragma once
#ifndef TLVLINK_QUANTIZE_PRIVATE
#error "onnx_internal.h is internal to quantize: include its public headers instead"
#endif
// Internals of the ONNX importer. The importer walks the ONNX graph once, in its (required)
// topological order, and builds a small IR of tlvlink operators in NHWC layout:
// - constants (initializers, Constant nodes, and shape arithmetic the exporter left behind,
//   e.g. torch's pads computation) stay in ONNX layout until an op consumes them;
// - every activation remembers its logical ONNX shape and how it is stored (Layout);
// - fusions (BatchNorm / bias / scale into Conv and Gemm, ReLU / ReLU6 into the op before,
//   zero Pad into the following Conv) edit the producing node in place, which is safe because
//   a node is only edited when the fused node is the sole reader of its output.
// emit.cc then writes the live part of the IR through ModelBuilder.

#include <onnx/onnx_pb.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/graph.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::quantize::onnx_internal {

// ---- constants (ONNX layout) ---------------------------------------------------------------

// Largest constant or activation the importer handles (elements); beyond it is an error.
inline constexpr int64_t kMaxElements = int64_t{1} << 30;

struct Constant {
  std::vector<int64_t> dims;  // empty: a scalar
  bool is_float = true;
  std::vector<float> f;    // when is_float
  std::vector<int64_t> i;  // otherwise (every integer type and bool)

  size_t elements() const { return is_float ? f.size() : i.size(); }
  int64_t int_at(size_t k) const { return is_float ? static_cast<int64_t>(f[k]) : i[k]; }
  float float_at(size_t k) const { return is_float ? f[k] : static_cast<float>(i[k]); }
};

// Product of dims; -1 if a dimension is negative or the product exceeds kMaxElements.
int64_t element_count(std::span<const int64_t> dims);
// "[1, 3, 224, 224]"
std::string dims_string(std::span<const int64_t> dims);

// Reads an initializer or a Constant node's tensor. Float data must be finite: NaN/Inf is an
// error naming `what` (e.g. "initializer 'conv.weight'") and the element.
Result<Constant> read_tensor(const onnx::TensorProto& t, const std::string& what);

// Element-wise permutation of a row-major array: out dims[k] = in dims[perm[k]].
template <typename T>
std::vector<T> transpose(std::span<const T> data, std::span<const int64_t> dims,
                         std::span<const int64_t> perm);

// ---- nodes and attributes ------------------------------------------------------------------

// The node's name, or its first output's name for an unnamed node.
std::string node_name(const onnx::NodeProto& node);
// "Conv node '/c/Conv'" (an unnamed node is named by its first output).
std::string node_label(const onnx::NodeProto& node);
// An error prefixed with the node's label: "Conv node '/c/Conv': <message>".
[[gnu::format(printf, 3, 4)]] Error node_error(ErrorCode code, const onnx::NodeProto& node,
                                               const char* format, ...);

const onnx::AttributeProto* find_attribute(const onnx::NodeProto& node, std::string_view name);
Result<int64_t> attr_int(const onnx::NodeProto& node, std::string_view name, int64_t fallback);
Result<float> attr_float(const onnx::NodeProto& node, std::string_view name, float fallback);
// Empty when absent.
Result<std::vector<int64_t>> attr_ints(const onnx::NodeProto& node, std::string_view name);
Result<std::string> attr_string(const onnx::NodeProto& node, std::string_view name,
                                std::string fallback);

// ---- IR ------------------------------------------------------------------------------------

// How an activation's logical (ONNX) layout maps onto its stored (tlvlink) layout.
enum class Layout : uint8_t {
  kPlain,     // same dims, same order
  kNhwc,      // rank 4: logical NCHW stored as NHWC
  kPermuted,  // rank 2 [N, F] flattened from NCHW: stored feature j is logical feature perm[j]
};

struct Value {
  std::string name;
  std::vector<int64_t> shape;  // logical (ONNX) shape; batch is 1
  Layout layout = Layout::kPlain;
  std::vector<int64_t> perm;  // kPermuted only
  int32_t producer = -1;      // node index; -1: the graph input
  int32_t uses = 0;           // readers: ONNX consumers of every name bound to it, graph outputs
};

// The tlvlink shape of a value (NHWC for kNhwc).
std::vector<int32_t> stored_shape(const Value& v);
// True when the stored elements are in the logical (row-major ONNX) order.
bool memory_is_logical(const Value& v);

struct ConstOperand {
  std::string name;
  std::vector<int32_t> shape;  // tlvlink layout
  std::vector<float> data;
};

struct Operand {
  int32_t value = -1;  // an activation; -1: `constant` holds the data
  ConstOperand constant;
};

struct Node {
  OpType type = OpType::kConv2D;
  std::string name;
  std::vector<Operand> inputs;
  int32_t output = -1;
  OpParams params;
  bool removed = false;  // folded into the node that reads it

  template <typename P>
  const P& get() const {
    return std::get<P>(params);
  }
};

// ---- the importer --------------------------------------------------------------------------

class Importer {
 public:
  Importer(const onnx::GraphProto& graph, int64_t opset);

  // Binds initializers and the input, converts every node, binds the outputs.
  Status run();

  const std::deque<Value>& values() const { return values_; }
  const std::deque<Node>& nodes() const { return nodes_; }
  int32_t input() const { return input_; }
  const std::vector<int32_t>& outputs() const { return outputs_; }
  size_t fused() const { return fused_; }

  // ---- for the op converters ----
  int64_t opset() const { return opset_; }
  // Input k is given (present and not the empty name).
  bool has_input(const onnx::NodeProto& node, int k) const;
  bool is_constant(const std::string& name) const;
  Result<int32_t> activation_input(const onnx::NodeProto& node, int k) const;
  Result<const Constant*> constant_input(const onnx::NodeProto& node, int k) const;
  Value& value(int32_t v) { return values_[static_cast<size_t>(v)]; }
  Node& node(int32_t n) { return nodes_[static_cast<size_t>(n)]; }

  // Appends a node and the activation it writes, bound to `output_name`; returns the node
  // index. Errors on an empty or too large shape.
  Result<int32_t> add_node(Node node, const std::string& output_name, std::vector<int64_t> shape,
                           Layout layout, std::vector<int64_t> perm = {});
  void bind_constant(const std::string& name, Constant c);
  // `name` now reads activation `v` (a fusion or an Identity): v gains name's readers and
  // loses the one node that consumed it to produce `name`.
  void alias(const std::string& name, int32_t v);
  // The node writing `v` if the caller is v's only reader (so the node may be edited in place).
  Node* sole_producer(int32_t v);
  void count_fused() { ++fused_; }

 private:
  Status bind_input(const onnx::ValueInfoProto& input);
  Status convert_node(const onnx::NodeProto& node);
  Status bind_output(const onnx::ValueInfoProto& output);

  struct Binding {
    int32_t value = -1;  // activation, or
    const Constant* constant = nullptr;
  };
  const onnx::GraphProto& graph_;
  int64_t opset_;
  std::deque<Value> values_;
  std::deque<Node> nodes_;
  std::deque<Constant> constants_;  // stable addresses for Binding::constant
  std::unordered_map<std::string, Binding> names_;
  std::unordered_map<std::string, int32_t> readers_;
  int32_t input_ = -1;
  std::vector<int32_t> outputs_;
  size_t fused_ = 0;
};

// ---- op converters (one ONNX node each) ----------------------------------------------------

using Converter = Status (*)(Importer& imp, const onnx::NodeProto& node);
// nullptr for an op type without a converter.
Converter find_converter(std::string_view op_type);

Status convert_conv(Importer& imp, const onnx::NodeProto& node);
Status convert_gemm(Importer& imp, const onnx::NodeProto& node);
Status convert_matmul(Importer& imp, const onnx::NodeProto& node);
Status convert_batch_norm(Importer& imp, const onnx::NodeProto& node);
Status convert_relu(Importer& imp, const onnx::NodeProto& node);
Status convert_clip(Importer& imp, const onnx::NodeProto& node);
Status convert_sigmoid(Importer& imp, const onnx::NodeProto& node);
Status convert_binary(Importer& imp, const onnx::NodeProto& node);  // Add, Sub, Mul, Div
Status convert_global_average_pool(Importer& imp, const onnx::NodeProto& node);
Status convert_reduce_mean(Importer& imp, const onnx::NodeProto& node);  // over H, W only
Status convert_max_pool(Importer& imp, const onnx::NodeProto& node);
Status convert_flatten(Importer& imp, const onnx::NodeProto& node);
Status convert_reshape(Importer& imp, const onnx::NodeProto& node);
Status convert_squeeze(Importer& imp, const onnx::NodeProto& node);  // Squeeze, Unsqueeze
Status convert_pad(Importer& imp, const onnx::NodeProto& node);
Status convert_identity(Importer& imp, const onnx::NodeProto& node);  // Identity, Dropout

// Folding into a Conv2D / FullyConnected that has no fused activation yet: the node writing
// `v` when the caller is its only reader, else nullptr.
Node* foldable_linear(Importer& imp, int32_t v);
// out[c] = a[c] * out[c] + b[c] folded into the node's weights and bias.
void fold_affine(Node& linear, std::span<const float> a, std::span<const float> b);
// Appends Mul(x, a) and/or Add(., b) with per-channel constants (BatchNorm on an activation).
Status emit_affine(Importer& imp, const onnx::NodeProto& node, int32_t x, std::vector<float> a,
                   std::vector<float> b);
// Fuses a clamp [lo, hi] into the producer of `x` when it is expressible as ReLU / ReLU6,
// else appends a Clamp node; the node's output 0 reads the result.
Status apply_clamp(Importer& imp, const onnx::NodeProto& node, int32_t x, float lo, float hi);

// ---- constant folding (shape arithmetic) ---------------------------------------------------

// Ops evaluated at import time when all their inputs are constants (Shape: when its input's
// shape is known, which it always is here).
bool const_evaluable(std::string_view op_type);
Result<Constant> evaluate_constant(Importer& imp, const onnx::NodeProto& node);

// ---- writing the model (emit.cc) -----------------------------------------------------------

// Writes the live part of the IR (what the outputs depend on) as a .tlvm file; counts the
// operators written into `operators`.
Result<std::vector<std::byte>> emit_model(const Importer& imp, const MetadataSpec& metadata,
                                          size_t& operators);

// ---- shared shape helpers ------------------------------------------------------------------

// Target shape of Reshape (0 copies the input dimension unless allowzero, -1 is inferred).
Result<std::vector<int64_t>> reshape_target(const onnx::NodeProto& node,
                                            std::span<const int64_t> in, const Constant& shape,
                                            bool allowzero);
// ONNX multidirectional broadcasting.
Result<std::vector<int64_t>> broadcast_dims(const onnx::NodeProto& node, std::span<const int64_t> a,
                                            std::span<const int64_t> b);

// One spatial axis of a Conv or MaxPool window.
struct Window {
  int64_t kernel = 1, stride = 1, dilation = 1, pad_begin = 0, pad_end = 0;
};
// Resolves auto_pad (NOTSET / SAME_UPPER / SAME_LOWER / VALID) into explicit pads, checks the
// window against the input and returns the output size (floor mode).
Result<int64_t> window_output(const onnx::NodeProto& node, int64_t in, Window& w,
                              std::string_view auto_pad);
using Windows = std::array<Window, 2>;  // height, width
// Reads kernel_shape / strides / dilations / pads / auto_pad for a 2-D Conv or MaxPool.
Result<Windows> read_windows(const onnx::NodeProto& node, std::span<const int64_t> kernel,
                             std::string* auto_pad);

// A constant broadcast against activation `act`, in act's stored layout. Errors when the
// broadcast cannot be expressed without moving act's data.
Result<ConstOperand> constant_for(const onnx::NodeProto& node, const Value& act, const Constant& c,
                                  std::string name);
// The constant as one value per channel (act's last stored axis) when it broadcasts that way
// and does not enlarge the activation; empty otherwise.
std::vector<float> per_channel(const ConstOperand& c, const Value& act);

}  // namespace tlvlink::quantize::onnx_internal
