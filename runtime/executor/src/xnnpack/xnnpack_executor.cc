// The XNNPACK subgraph executor: builds one subgraph from the model, creates the runtime (packs
// weights), binds executor-owned external buffers once, and per frame only checks float inputs,
// invokes, and optionally checks float outputs. Nothing is allocated in invoke().
#include <optional>
#include <vector>

#include "tlvlink/executor.h"
#include "xnnpack/build_subgraph.h"
#include "xnnpack/define_tensors.h"
#include "xnnpack/owned_memory.h"
#include "xnnpack/xnn_api.h"

namespace tlvlink {
namespace {

std::span<const float> as_floats(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const float*>(bytes.data()), bytes.size() / sizeof(float)};
}

// Non-copyable and non-movable: XNNPACK holds pointers into memory_ and the pool.
class XnnpackExecutor final : public Executor {
 public:
  XnnpackExecutor(const Model& model, const ExecutorOptions& options)
      : graph_(model.graph()), options_(options), readable_(graph_.tensors.size()) {}
  XnnpackExecutor(const XnnpackExecutor&) = delete;
  XnnpackExecutor& operator=(const XnnpackExecutor&) = delete;

  Status build();

  ExecutorKind kind() const override { return ExecutorKind::kXnnpack; }
  std::span<std::byte> input(size_t i) override {
    return i < inputs_.size() ? inputs_[i] : std::span<std::byte>();
  }
  std::span<const std::byte> output(size_t i) const override {
    if (i >= graph_.outputs.size()) return {};
    return readable_[static_cast<size_t>(graph_.outputs[i])];
  }
  Status invoke() override;
  Status invoke_trusted_inputs() override;
  Result<std::span<const std::byte>> tensor(int32_t index) const override;

 private:
  std::vector<xnn::ExternalFlags> external_flags() const;

  const Graph& graph_;
  const ExecutorOptions options_;
  // Declaration order is destruction order in reverse: the runtime goes first, then the pool,
  // then the memory it pointed into.
  xnn::OwnedMemory memory_;
  std::vector<std::span<const std::byte>> readable_;   // per tensor; empty: not kept
  std::vector<std::span<std::byte>> inputs_;           // per graph input
  std::vector<int32_t> float_inputs_, float_outputs_;  // tensors checked for NaN/Inf
  FloatInputLimit input_limit_;                        // float_input_limit(graph_)
  std::optional<xnn::ThreadPool> pool_;
  std::optional<xnn::Runtime> runtime_;
};

std::vector<xnn::ExternalFlags> XnnpackExecutor::external_flags() const {
  std::vector<xnn::ExternalFlags> flags(graph_.tensors.size());
  for (int32_t t : graph_.inputs) flags[static_cast<size_t>(t)].input = true;
  for (int32_t t : graph_.outputs) flags[static_cast<size_t>(t)].output = true;
  if (options_.expose_all_tensors) {
    // Every activation becomes an external output with its own buffer (calibration reads them).
    for (size_t t = 0; t < flags.size(); ++t) {
      if (!graph_.tensors[t].is_constant() && !flags[t].input) flags[t].output = true;
    }
  }
  return flags;
}

Status XnnpackExecutor::build() {
  TLV_TRY(xnn::initialize());
  const std::vector<xnn::ExternalFlags> flags = external_flags();

  // Buffers for external values, bound once below. Constants are readable in place.
  std::vector<xnn::ExternalBinding> bindings;
  std::vector<std::span<std::byte>> writable(graph_.tensors.size());
  for (size_t t = 0; t < graph_.tensors.size(); ++t) {
    const Tensor& tensor = graph_.tensors[t];
    if (tensor.is_constant()) {
      readable_[t] = tensor.data;
    } else if (flags[t].input || flags[t].output) {
      TLV_ASSIGN_OR_RETURN(std::span<std::byte> buffer, memory_.allocate(tensor.bytes()));
      readable_[t] = writable[t] = buffer;
      bindings.push_back({static_cast<uint32_t>(t), buffer.data()});
    }
  }
  for (int32_t t : graph_.inputs) {
    // A graph input is an activation (validated), so it has a buffer.
    inputs_.push_back(writable[static_cast<size_t>(t)]);
    if (graph_.tensor(t).dtype == DType::kFloat32) float_inputs_.push_back(t);
  }
  for (int32_t t : graph_.outputs) {
    if (graph_.tensor(t).dtype == DType::kFloat32) float_outputs_.push_back(t);
  }
  input_limit_ = float_input_limit(graph_);

  std::vector<int32_t> ops(graph_.operators.size());
  for (size_t i = 0; i < ops.size(); ++i) ops[i] = static_cast<int32_t>(i);
  TLV_ASSIGN_OR_RETURN(xnn::Subgraph subgraph, xnn::build_subgraph(graph_, flags, ops, memory_));
  TLV_ASSIGN_OR_RETURN(xnn::ThreadPool pool, xnn::ThreadPool::create(options_.threads));
  pool_.emplace(std::move(pool));
  Result<xnn::Runtime> runtime = xnn::Runtime::create(subgraph, *pool_);
  if (!runtime.ok()) return xnn::diagnose_runtime_failure(graph_, runtime.error());
  runtime_.emplace(std::move(runtime).value());
  // The subgraph is deleted on return; the runtime no longer needs it.
  return runtime_->setup(bindings);
}

Status XnnpackExecutor::invoke() {
  for (int32_t t : float_inputs_) {
    const Status s = check_float_input(as_floats(readable_[static_cast<size_t>(t)]), input_limit_,
                                       graph_, graph_.tensor(t).name);
    if (!s.ok()) return s.error().with_context("graph input tensor %d", t);
  }
  return invoke_trusted_inputs();
}

Status XnnpackExecutor::invoke_trusted_inputs() {
  TLV_TRY(runtime_->invoke());
  if (options_.check_outputs) {
    for (int32_t t : float_outputs_) {
      const Status s =
          check_finite(as_floats(readable_[static_cast<size_t>(t)]), graph_.tensor(t).name);
      if (!s.ok()) return s.error().with_context("graph output tensor %d", t);
    }
  }
  return Status();
}

Result<std::span<const std::byte>> XnnpackExecutor::tensor(int32_t index) const {
  TLV_ENSURE(index >= 0 && static_cast<size_t>(index) < graph_.tensors.size(),
             ErrorCode::kInvalidArgument, "tensor index %d out of range (model has %zu tensors)",
             index, graph_.tensors.size());
  const std::span<const std::byte> data = readable_[static_cast<size_t>(index)];
  const std::string_view name = graph_.tensor(index).name;
  TLV_ENSURE(!data.empty(), ErrorCode::kInvalidState,
             "tensor '%.*s' (#%d) is not kept by the XNNPACK executor (intermediate activation; "
             "create the executor with expose_all_tensors to read it)",
             static_cast<int>(name.size()), name.data(), index);
  return data;
}

}  // namespace

Result<std::unique_ptr<Executor>> make_xnnpack_executor(const Model& model,
                                                        const ExecutorOptions& options) {
  auto executor = std::make_unique<XnnpackExecutor>(model, options);
  TLV_TRY(executor->build());
  return std::unique_ptr<Executor>(std::move(executor));
}

}  // namespace tlvlink
