// tlvlink verify MODEL: runs the golden I/O pairs embedded in the model and compares.
// Tolerances: an int8 output within 1 LSB (XNNPACK and the reference may round half-way cases
// differently); a float output behind a Dequantize within 1 LSB of that int8 tensor's scale;
// a float output of a float graph within 1e-4 of the output's largest magnitude (summation order
// differs between kernels; per-element relative error is meaningless near zero).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "cli/common.h"

namespace tlvlink::cli {
namespace {

constexpr double kFloatRelTolerance = 1e-4;
constexpr double kInt8LsbTolerance = 1.0;
// Float slack on a 1-LSB dequantized comparison (the dequantize itself rounds).
constexpr double kLsbSlack = 1.0 + 1e-5;

struct VerifyOptions {
  std::string model;
  ExecutorFlags exec;
};

// The quantized tensor a float graph output is dequantized from, if any.
const Tensor* dequantized_from(const Graph& g, int32_t output) {
  for (const Operator& op : g.operators) {
    if (op.output == output && op.type == OpType::kDequantize) return &g.tensor(op.inputs[0]);
  }
  return nullptr;
}

int run_verify(const VerifyOptions& o) {
  auto model = load_model(o.model);
  if (!model.ok()) return report_error("verify", model.error());
  const Model& m = **model;
  const Graph& g = m.graph();
  if (m.metadata().golden.empty()) {
    return report_error("verify", Error::make(ErrorCode::kInvalidState,
                                              "%s has no golden pairs to verify", o.model.c_str()));
  }
  auto exec = create_executor(m, o.exec);
  if (!exec.ok()) return report_error("verify", exec.error());
  Executor& e = **exec;
  const Tensor& out = g.tensor(g.outputs[0]);
  const Tensor* q = out.dtype == DType::kFloat32 ? dequantized_from(g, g.outputs[0]) : nullptr;
  bool all_pass = true;
  for (size_t i = 0; i < m.metadata().golden.size(); ++i) {
    const GoldenPair& pair = m.metadata().golden[i];
    std::memcpy(e.input(0).data(), pair.input.data(), pair.input.size());
    if (Status s = e.invoke(); !s.ok())
      return report_error("verify", s.error().with_context("golden pair %zu", i));
    const std::vector<float> got = output_as_floats(out, e.output(0));
    const std::vector<float> want = output_as_floats(out, pair.output);
    double max_err = 0, max_ref = 0;
    for (size_t k = 0; k < got.size(); ++k) {
      max_err =
          std::max(max_err, std::fabs(static_cast<double>(got[k]) - static_cast<double>(want[k])));
      max_ref = std::max(max_ref, std::fabs(static_cast<double>(want[k])));
    }
    double tolerance;
    const char* rule;
    if (out.dtype == DType::kInt8) {
      tolerance = kInt8LsbTolerance *
                  (out.quant.quantized() ? static_cast<double>(out.quant.scale[0]) : 1.0) *
                  kLsbSlack;
      rule = "1 LSB";
    } else if (q != nullptr) {
      tolerance = kInt8LsbTolerance * static_cast<double>(q->quant.scale[0]) * kLsbSlack;
      rule = "1 LSB of the dequantized int8 output";
    } else {
      tolerance = kFloatRelTolerance * std::max(max_ref, 1e-30);
      rule = "1e-4 x max|golden|";
    }
    const bool pass = max_err <= tolerance;
    all_pass = all_pass && pass;
    std::printf("golden pair %zu: max abs error %.4g (tolerance %.4g: %s), %s\n", i, max_err,
                tolerance, rule, pass ? "PASS" : "FAIL");
  }
  std::printf("verify %s with the %s executor: %s\n", o.model.c_str(), executor_kind_name(e.kind()),
              all_pass ? "PASS" : "FAIL");
  return all_pass ? kExitOk : kExitFailure;
}

}  // namespace

void add_verify_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<VerifyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "verify", "Run the model's embedded golden I/O pairs and compare (exit 1 on mismatch)");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  o->exec.add_to(*cmd);
  cmd->footer(std::string(kExitCodeFooter) +
              "\nTolerances: int8 outputs 1 LSB; dequantized int8 outputs 1 LSB of their scale; "
              "float models 1e-4 x the largest golden magnitude.");
  cmd->callback([o, &exit_code] { exit_code = run_verify(*o); });
}

}  // namespace tlvlink::cli
