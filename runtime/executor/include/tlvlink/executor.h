#pragma once
// The one interface both executors implement. An executor borrows its Model (the model must
// outlive it), allocates everything at creation (XNNPACK: weights packed once, runtime set up
// once) and performs no heap allocation in invoke().
//
// Typical use:
//   auto model = Model::load_file("m.tlvm");            // Result<unique_ptr<Model>>
//   auto exec = make_executor(**model, ExecutorKind::kXnnpack, {.threads = 2});
//   std::memcpy((*exec)->input(0).data(), frame, (*exec)->input(0).size());
//   if (auto s = (*exec)->invoke(); !s.ok()) log(s.error().message());
//   use((*exec)->output(0));

#include <cfloat>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "tlvlink/error.h"
#include "tlvlink/model.h"

namespace tlvlink {

enum class ExecutorKind : uint8_t { kReference = 0, kXnnpack = 1 };
const char* executor_kind_name(ExecutorKind kind);
// Parses "reference" / "xnnpack".
Result<ExecutorKind> parse_executor_kind(std::string_view name);

struct ExecutorOptions {
  int threads = 1;                  // XNNPACK thread pool size (1 = no pool); reference ignores it
  bool expose_all_tensors = false;  // make every activation readable via tensor() (calibration,
                                    // per-layer error reports); costs memory, not speed
  bool check_outputs = true;        // after invoke, reject NaN/Inf in float outputs
};

class Executor {
 public:
  virtual ~Executor() = default;
  virtual ExecutorKind kind() const = 0;

  // Buffer for graph input i, sized exactly Graph::tensor(inputs[i]).bytes(). Stable address.
  virtual std::span<std::byte> input(size_t i) = 0;
  // Buffer holding graph output i after a successful invoke(). Stable address.
  virtual std::span<const std::byte> output(size_t i) const = 0;

  // Runs the graph. Float inputs containing NaN/Inf, or a magnitude beyond float_input_limit,
  // are rejected before anything runs (ErrorCode::kNonFiniteValue naming the input, the same
  // message on every executor); with check_outputs, so are non-finite float outputs.
  virtual Status invoke() = 0;
  // The same without the input scan, for inputs finite by construction: a frame written by a
  // preprocessing plan from uint8 pixels (image::PreprocessPlan::outputs_finite()). The camera
  // path must not pay for a check that cannot fail there (the scan costs a few percent of a small
  // model's invoke); user-supplied float tensors go through invoke().
  virtual Status invoke_trusted_inputs() = 0;

  // Contents of any tensor after invoke(): constants always; activations only with
  // expose_all_tensors (otherwise graph inputs/outputs only). Error if not available.
  virtual Result<std::span<const std::byte>> tensor(int32_t index) const = 0;
};

Result<std::unique_ptr<Executor>> make_reference_executor(const Model& model,
                                                          const ExecutorOptions& options = {});
// Error kModelUnsupported when the build has no XNNPACK (TLVLINK_WITH_XNNPACK=OFF).
Result<std::unique_ptr<Executor>> make_xnnpack_executor(const Model& model,
                                                        const ExecutorOptions& options = {});
Result<std::unique_ptr<Executor>> make_executor(const Model& model, ExecutorKind kind,
                                                const ExecutorOptions& options = {});

// Shared per-frame checks (cheap, no allocation). `what` names the tensor in the error. The scan
// is branch-free over the exponent bits (vectorised by the compiler); only a failing tensor is
// walked again to name the first bad element.
Status check_finite(std::span<const float> values, std::string_view what);

// The largest magnitude a float graph input may hold with no float value inside the graph able
// to overflow float32 to Inf (and from there to NaN): interval bounds from the weights (a conv /
// FC multiplies a bound by max_c sum|w_c|, clamps and int8 tensors cap it), with a 2x margin for
// summation order. FLT_MAX when nothing can overflow (e.g. a Quantize first). Both executors
// compute it at creation and check inputs against it in invoke(): overflow is detected before it
// happens, in the same place and with the same message on both, where checking after the fact
// cannot agree (XNNPACK's fused clamps turn an overflowed NaN into a finite value on x86, the
// reference's keep it, and ARM kernels differ again).
struct FloatInputLimit {
  float limit = FLT_MAX;
  int32_t op = -1;  // the first operator that could overflow just above the limit (-1: none)
};
FloatInputLimit float_input_limit(const Graph& graph);
// check_finite, and |x| <= limit (kNonFiniteValue naming the element, its value, the limit and
// the operator that would overflow first).
Status check_float_input(std::span<const float> values, const FloatInputLimit& limit,
                         const Graph& graph, std::string_view what);

}  // namespace tlvlink
