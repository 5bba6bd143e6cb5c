// libFuzzer target: arbitrary bytes into Model::load. Anything the loader accepts is then run
// once through the reference executor, so a validation gap that lets an executor read out of
// bounds is found too (ASan/UBSan make it fatal).
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"

namespace {

// Keep each execution fast: skip running models whose activations exceed this.
constexpr size_t kMaxRunBytes = size_t{1} << 20;

size_t activation_bytes(const tlvlink::Graph& graph) {
  size_t total = 0;
  for (const auto& t : graph.tensors) {
    if (!t.is_constant()) total += t.bytes();
  }
  return total;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto bytes = std::span(reinterpret_cast<const std::byte*>(data), size);
  // The checksum would reject nearly every mutation before the semantic checks see it.
  auto model = tlvlink::Model::load(bytes, {.verify_checksum = false});
  if (!model.ok()) {
    // Every rejection must say something.
    if (std::strlen(model.error().message()) == 0) __builtin_trap();
    return 0;
  }
  const tlvlink::Model& m = **model;
  if (activation_bytes(m.graph()) > kMaxRunBytes) return 0;
  auto exec = tlvlink::make_reference_executor(m);
  if (!exec.ok()) return 0;
  for (size_t i = 0; i < m.graph().inputs.size(); ++i) {
    auto in = (*exec)->input(i);
    std::memset(in.data(), 0, in.size());
  }
  (void)(*exec)->invoke();
  return 0;
}
