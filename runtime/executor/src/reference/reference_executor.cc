// The portable reference executor: plain C++ loops, no XNNPACK. It is the oracle the XNNPACK
// executor is tested against and the fallback on boards without XNNPACK.
//
// At creation it lays every activation out in one arena (reference/arena.h), binds each
// operator's tensors to their buffers and picks its kernel; invoke() only checks float inputs,
// runs the kernels in order and checks float outputs. Every activation keeps its own buffer, so
// tensor() serves all of them whether or not expose_all_tensors is set.
#include <vector>

#include "reference/arena.h"
#include "reference/kernels.h"
#include "tlvlink/executor.h"

namespace tlvlink {
namespace {

using reference::Arena;
using reference::Kernel;
using reference::OpArgs;

std::span<const float> as_floats(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const float*>(bytes.data()), bytes.size() / sizeof(float)};
}

Kernel select_kernel(const OpArgs& args) {
  switch (args.op->type) {
    case OpType::kConv2D: return reference::select_conv2d(args);
    case OpType::kFullyConnected: return reference::select_fully_connected(args);
    case OpType::kAdd:
    case OpType::kMul:
    case OpType::kClamp:
    case OpType::kSigmoid: return reference::select_elementwise(args);
    case OpType::kGlobalAveragePool:
    case OpType::kMaxPool2D: return reference::select_pooling(args);
    case OpType::kPad:
    case OpType::kReshape: return reference::select_pad_reshape(args);
    case OpType::kResizeBilinear: return reference::select_resize_bilinear(args);
    case OpType::kQuantize:
    case OpType::kDequantize: return reference::select_convert(args);
  }
  return nullptr;
}

// Non-copyable and non-movable: the bound OpArgs point into arena_ and the borrowed graph.
class ReferenceExecutor final : public Executor {
 public:
  ReferenceExecutor(const Model& model, Arena arena)
      : graph_(model.graph()), arena_(std::move(arena)) {}
  ReferenceExecutor(const ReferenceExecutor&) = delete;
  ReferenceExecutor& operator=(const ReferenceExecutor&) = delete;

  Status build(const ExecutorOptions& options);

  ExecutorKind kind() const override { return ExecutorKind::kReference; }
  std::span<std::byte> input(size_t i) override {
    return i < graph_.inputs.size() ? arena_.slot(graph_.inputs[i]) : std::span<std::byte>();
  }
  std::span<const std::byte> output(size_t i) const override {
    return i < graph_.outputs.size() ? arena_.slot(graph_.outputs[i]) : std::span<std::byte>();
  }
  Status invoke() override;
  Status invoke_trusted_inputs() override;
  Result<std::span<const std::byte>> tensor(int32_t index) const override;

 private:
  Status bind(size_t op_index);
  Status check_floats(const std::vector<int32_t>& tensors, const char* role) const;

  const Graph& graph_;
  Arena arena_;
  bool check_outputs_ = true;
  FloatInputLimit input_limit_;  // float_input_limit(graph_)
  std::vector<OpArgs> args_;     // per operator, in execution order
  std::vector<Kernel> kernels_;
  std::vector<int32_t> float_inputs_, float_outputs_;  // checked for NaN/Inf
};

Status ReferenceExecutor::bind(size_t op_index) {
  const Operator& op = graph_.operators[op_index];
  OpArgs args;
  args.op = &op;
  for (size_t i = 0; i < op.input_count && i < args.in.size(); ++i) {
    const int32_t t = op.inputs[i];
    if (t == kNoTensor) continue;
    const Tensor& tensor = graph_.tensor(t);
    args.in[i] = &tensor;
    args.in_data[i] = tensor.is_constant() ? tensor.data.data() : arena_.slot(t).data();
  }
  args.out = &graph_.tensor(op.output);
  args.out_data = arena_.slot(op.output).data();

  const std::string_view name = op.name;
  const char* dtype = dtype_name(args.in[0]->dtype);
  // XNNPACK only takes symmetric int8 weights; the int8 kernels rely on it too.
  if ((op.type == OpType::kConv2D || op.type == OpType::kFullyConnected) &&
      args.in[1]->dtype == DType::kInt8 && args.in[1]->quant.zero_point[0] != 0) {
    return Error::make(ErrorCode::kModelUnsupported,
                       "operator %zu %s '%.*s': int8 weights have zero point %d; only symmetric "
                       "weights (zero point 0) are supported",
                       op_index, op_type_name(op.type), static_cast<int>(name.size()), name.data(),
                       args.in[1]->quant.zero_point[0]);
  }
  const Kernel kernel = select_kernel(args);
  TLV_ENSURE(kernel != nullptr, ErrorCode::kModelUnsupported,
             "operator %zu %s '%.*s': the reference executor has no %s kernel for %s input",
             op_index, op_type_name(op.type), static_cast<int>(name.size()), name.data(),
             op_type_name(op.type), dtype);
  args_.push_back(args);
  kernels_.push_back(kernel);
  return Status();
}

Status ReferenceExecutor::build(const ExecutorOptions& options) {
  check_outputs_ = options.check_outputs;  // threads and expose_all_tensors do not apply
  args_.reserve(graph_.operators.size());
  kernels_.reserve(graph_.operators.size());
  for (size_t i = 0; i < graph_.operators.size(); ++i) TLV_TRY(bind(i));
  for (int32_t t : graph_.inputs) {
    if (graph_.tensor(t).dtype == DType::kFloat32) float_inputs_.push_back(t);
  }
  for (int32_t t : graph_.outputs) {
    if (graph_.tensor(t).dtype == DType::kFloat32) float_outputs_.push_back(t);
  }
  input_limit_ = float_input_limit(graph_);
  return Status();
}

Status ReferenceExecutor::check_floats(const std::vector<int32_t>& tensors,
                                       const char* role) const {
  for (int32_t t : tensors) {
    const Status s = check_finite(as_floats(arena_.slot(t)), graph_.tensor(t).name);
    if (!s.ok()) return s.error().with_context("graph %s tensor %d", role, t);
  }
  return Status();
}

Status ReferenceExecutor::invoke() {
  for (int32_t t : float_inputs_) {
    const Status s =
        check_float_input(as_floats(arena_.slot(t)), input_limit_, graph_, graph_.tensor(t).name);
    if (!s.ok()) return s.error().with_context("graph input tensor %d", t);
  }
  return invoke_trusted_inputs();
}

Status ReferenceExecutor::invoke_trusted_inputs() {
  for (size_t i = 0; i < kernels_.size(); ++i) kernels_[i](args_[i]);
  if (check_outputs_) TLV_TRY(check_floats(float_outputs_, "output"));
  return Status();
}

Result<std::span<const std::byte>> ReferenceExecutor::tensor(int32_t index) const {
  TLV_ENSURE(index >= 0 && static_cast<size_t>(index) < graph_.tensors.size(),
             ErrorCode::kInvalidArgument, "tensor index %d out of range (model has %zu tensors)",
             index, graph_.tensors.size());
  const Tensor& t = graph_.tensor(index);
  if (t.is_constant()) return t.data;
  return std::span<const std::byte>(arena_.slot(index));
}

}  // namespace

Result<std::unique_ptr<Executor>> make_reference_executor(const Model& model,
                                                          const ExecutorOptions& options) {
  TLV_ASSIGN_OR_RETURN(Arena arena, Arena::create(model.graph()));
  auto executor = std::make_unique<ReferenceExecutor>(model, std::move(arena));
  TLV_TRY(executor->build(options));
  return std::unique_ptr<Executor>(std::move(executor));
}

}  // namespace tlvlink
