// tlvlink verify MODEL: runs the golden I/O pairs embedded in the model and compares.
// Tolerances: cli/output_tolerance.h.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "cli/common.h"
#include "cli/output_tolerance.h"

namespace tlvlink::cli {
namespace {

struct VerifyOptions {
  std::string model;
  ExecutorFlags exec;
};

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
  bool all_pass = true;
  for (size_t i = 0; i < m.metadata().golden.size(); ++i) {
    const GoldenPair& pair = m.metadata().golden[i];
    std::memcpy(e.input(0).data(), pair.input.data(), pair.input.size());
    if (Status s = e.invoke(); !s.ok())
      return report_error("verify", s.error().with_context("golden pair %zu", i));
    const std::vector<float> got = output_as_floats(out, e.output(0));
    const std::vector<float> want = output_as_floats(out, pair.output);
    const OutputComparison c = compare_output(g, g.outputs[0], got, want);
    all_pass = all_pass && c.pass;
    std::printf("golden pair %zu: max abs error %.4g (tolerance %.4g: %s), %s\n", i,
                c.max_abs_error, c.tolerance, c.rule, c.pass ? "PASS" : "FAIL");
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
