// A board program on the minimal runtime (tests/minimal): links tlvlink_runtime alone, built
// without exceptions like target code, and runs every golden pair of each model given on every
// executor this build has. Without XNNPACK, asking for it must be a clear error, not a crash.
//   tlvlink_board_smoke MODEL.tlvm...      exit 0: all pairs within tolerance
// Tolerances are those of `tlvlink verify` (tools/cli/output_tolerance.h), which this program
// cannot link: int8 outputs 1 LSB; a float output made by Dequantize 1 LSB of its source's
// scale; other float outputs 1e-4 x the largest golden magnitude.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include "tlvlink/tlvlink.h"

namespace {

using namespace tlvlink;

constexpr double kFloatRelTolerance = 1e-4;  // summation order differs between kernels
constexpr double kLsbSlack = 1.0 + 1e-5;     // the dequantize itself rounds

float value_at(const Tensor& t, std::span<const std::byte> bytes, size_t i) {
  if (t.dtype == DType::kInt8) return static_cast<float>(static_cast<int8_t>(bytes[i]));
  float f;
  std::memcpy(&f, bytes.data() + i * sizeof(float), sizeof(float));
  return f;
}

// Allowed |got - golden| for graph output `output` (0: compare exactly).
double tolerance(const Graph& g, int32_t output, double max_golden) {
  const Tensor& out = g.tensor(output);
  if (out.dtype == DType::kInt8) return kLsbSlack;  // values compared in LSB
  for (const Operator& op : g.operators) {
    if (op.output == output && op.type == OpType::kDequantize)
      return static_cast<double>(g.tensor(op.inputs[0]).quant.scale[0]) * kLsbSlack;
  }
  return kFloatRelTolerance * max_golden;
}

// Runs the model's golden pairs on `exec`; returns the number of failing pairs.
int run_pairs(const char* path, const Model& model, Executor& exec) {
  const Graph& g = model.graph();
  const Tensor& out = g.tensor(g.outputs[0]);
  int failures = 0;
  for (size_t p = 0; p < model.metadata().golden.size(); ++p) {
    const GoldenPair& pair = model.metadata().golden[p];
    if (pair.input.size() != exec.input(0).size() || pair.output.size() != exec.output(0).size()) {
      std::printf("%s pair %zu: sizes differ from the graph's input/output\n", path, p);
      ++failures;
      continue;
    }
    std::memcpy(exec.input(0).data(), pair.input.data(), pair.input.size());
    if (Status s = exec.invoke(); !s.ok()) {
      std::printf("%s pair %zu: invoke failed: %s\n", path, p, s.error().message());
      ++failures;
      continue;
    }
    const size_t n = out.shape.elements();
    double max_golden = 0, max_error = 0;
    for (size_t i = 0; i < n; ++i) {
      const double want = value_at(out, pair.output, i);
      const double got = value_at(out, exec.output(0), i);
      max_golden = std::max(max_golden, std::fabs(want));
      // NaN must fail, never compare as "not greater".
      max_error = std::isfinite(got - want) ? std::max(max_error, std::fabs(got - want))
                                            : std::numeric_limits<double>::infinity();
    }
    const double allowed = tolerance(g, g.outputs[0], max_golden);
    const bool pass = max_error <= allowed;
    failures += pass ? 0 : 1;
    std::printf("%s %s pair %zu: max abs error %.4g (allowed %.4g) %s\n", path,
                executor_kind_name(exec.kind()), p, max_error, allowed, pass ? "PASS" : "FAIL");
  }
  return failures;
}

int check_model(const char* path) {
  auto model = Model::load_file(path);
  if (!model.ok()) {
    std::printf("%s: %s\n", path, model.error().message());
    return 1;
  }
  const Model& m = **model;
  if (m.metadata().golden.empty()) {
    std::printf("%s: no golden pairs\n", path);
    return 1;
  }
  int failures = 0;
  for (ExecutorKind kind : {ExecutorKind::kReference, ExecutorKind::kXnnpack}) {
    auto exec = make_executor(m, kind, {.threads = 2});
#if defined(TLVLINK_HAVE_XNNPACK)
    constexpr bool kHaveXnnpack = true;
#else
    constexpr bool kHaveXnnpack = false;
#endif
    if (kind == ExecutorKind::kXnnpack && !kHaveXnnpack) {
      const bool clear = !exec.ok() && exec.error().code() == ErrorCode::kModelUnsupported;
      std::printf("%s xnnpack: %s (%s)\n", path, clear ? "unavailable as expected" : "FAIL",
                  exec.ok() ? "created in a build without XNNPACK" : exec.error().message());
      failures += clear ? 0 : 1;
      continue;
    }
    if (!exec.ok()) {
      std::printf("%s %s: %s\n", path, executor_kind_name(kind), exec.error().message());
      ++failures;
      continue;
    }
    failures += run_pairs(path, m, **exec);
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODEL.tlvm...\n", argv[0]);
    return 2;
  }
  int failures = 0;
  for (int i = 1; i < argc; ++i) failures += check_model(argv[i]);
  std::printf("board smoke: %s\n", failures == 0 ? "PASS" : "FAIL");
  return failures == 0 ? 0 : 1;
}
