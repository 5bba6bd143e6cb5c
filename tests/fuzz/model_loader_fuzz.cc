// libFuzzer target: arbitrary bytes into Model::load. Anything the loader accepts is then given
// to both executors (reference and, in XNNPACK builds, XNNPACK) and run once, so a validation
// gap that lets an executor read out of bounds, abort or trap is found too (ASan/UBSan make it
// fatal). An executor may refuse a model the loader accepted, but only with an error value.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"

namespace {

// Keep each execution fast. Executors are created only when all activations fit in
// kMaxCreateBytes (creation allocates them; XNNPACK also packs the weights, linear in the file
// size), and invoked only when activations fit in kMaxInvokeBytes and Conv2D/FC work is at
// most kMaxInvokeMacs: ~1 M MACs run in ~10 ms in the ASan-instrumented reference kernels,
// whereas the 96-px reference encoder seeds (~21 M MACs) take ~0.25 s per mutant and would
// starve the loader of executions (loading and creating both executors: ~7 ms). Other ops
// cost O(activation elements).
constexpr size_t kMaxCreateBytes = size_t{16} << 20;
constexpr size_t kMaxInvokeBytes = size_t{1} << 20;
constexpr uint64_t kMaxInvokeMacs = uint64_t{1} << 20;

size_t activation_bytes(const tlvlink::Graph& graph) {
  size_t total = 0;
  for (const auto& t : graph.tensors) {
    if (!t.is_constant()) total += t.bytes();
  }
  return total;
}

// Multiply-accumulates of Conv2D and FC: output elements x weights per output channel
// (kh*kw*cin/groups, or cin). Stops counting past the cap (a sum of validated sizes, but many).
uint64_t conv_fc_macs(const tlvlink::Graph& graph) {
  uint64_t total = 0;
  for (const auto& op : graph.operators) {
    using tlvlink::OpType;
    if (op.type != OpType::kConv2D && op.type != OpType::kFullyConnected) continue;
    const tlvlink::Shape& w = graph.tensor(op.inputs[1]).shape;
    total += graph.tensor(op.output).shape.elements() * (w.elements() / static_cast<size_t>(w[0]));
    if (total > kMaxInvokeMacs) break;
  }
  return total;
}

// Every refusal must say something.
void check_message(const tlvlink::Error& e) {
  if (std::strlen(e.message()) == 0) __builtin_trap();
}

void run(const tlvlink::Model& m, tlvlink::ExecutorKind kind, bool invoke) {
  // Without XNNPACK in the build, make_executor(kXnnpack) is a kModelUnsupported error.
  auto exec = tlvlink::make_executor(m, kind);
  if (!exec.ok()) {
    check_message(exec.error());
    return;
  }
  if (!invoke) return;
  for (size_t i = 0; i < m.graph().inputs.size(); ++i) {
    auto in = (*exec)->input(i);
    std::memset(in.data(), 0, in.size());
  }
  if (const tlvlink::Status s = (*exec)->invoke(); !s.ok()) check_message(s.error());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto bytes = std::span(reinterpret_cast<const std::byte*>(data), size);
  // The whole-file hash would reject every mutation before the parser sees it; with it off, the
  // integrity trailer is still parsed when present and the file is read whole when not.
  auto model = tlvlink::Model::load(bytes, {.verify_checksum = false});
  if (!model.ok()) {
    check_message(model.error());
    return 0;
  }
  const tlvlink::Model& m = **model;
  const size_t activations = activation_bytes(m.graph());
  if (activations > kMaxCreateBytes) return 0;
  const bool invoke = activations <= kMaxInvokeBytes && conv_fc_macs(m.graph()) <= kMaxInvokeMacs;
  run(m, tlvlink::ExecutorKind::kReference, invoke);
  run(m, tlvlink::ExecutorKind::kXnnpack, invoke);
  return 0;
}
