// The executor-independent functions of executor.h: names, parsing, dispatch and the
// per-frame finiteness check both executors run on float inputs and outputs.
#include <cmath>

#include "tlvlink/executor.h"

namespace tlvlink {

const char* executor_kind_name(ExecutorKind kind) {
  switch (kind) {
    case ExecutorKind::kReference: return "reference";
    case ExecutorKind::kXnnpack: return "xnnpack";
  }
  return "unknown";
}

Result<ExecutorKind> parse_executor_kind(std::string_view name) {
  if (name == "reference") return ExecutorKind::kReference;
  if (name == "xnnpack") return ExecutorKind::kXnnpack;
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown executor '%.*s' (expected 'reference' or 'xnnpack')",
                     static_cast<int>(name.size()), name.data());
}

Result<std::unique_ptr<Executor>> make_executor(const Model& model, ExecutorKind kind,
                                                const ExecutorOptions& options) {
  switch (kind) {
    case ExecutorKind::kReference: return make_reference_executor(model, options);
    case ExecutorKind::kXnnpack: return make_xnnpack_executor(model, options);
  }
  return Error::make(ErrorCode::kInvalidArgument, "unknown executor kind %d",
                     static_cast<int>(kind));
}

Status check_finite(std::span<const float> values, std::string_view what) {
  // An IEEE float is NaN or Inf exactly when its 8 exponent bits are all ones.
  constexpr uint32_t kExponent = 0x7f800000u;
  uint32_t bad = 0;
  const auto* bits = reinterpret_cast<const uint32_t*>(values.data());
  for (size_t i = 0; i < values.size(); ++i)
    bad |= static_cast<uint32_t>((bits[i] & kExponent) == kExponent);
  if (bad == 0) return Status();
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      return Error::make(ErrorCode::kNonFiniteValue,
                         "%.*s: element %zu of %zu is %g; NaN and Inf are rejected",
                         static_cast<int>(what.size()), what.data(), i, values.size(),
                         static_cast<double>(values[i]));
    }
  }
  return Status();
}

}  // namespace tlvlink
