// tlvlink verify MODEL [--public-key PUB]: the file's hash (at load) and, with a key, its
// signature; then the golden I/O pairs embedded in the model and their head outputs
// (runtime/verify: the rules and their tolerances).

#include <cstdio>

#include "common.h"
#include "tlvlink/verify/golden.h"

namespace tlvlink::cli {
namespace {

struct VerifyOptions {
  std::string model, public_key;
  ExecutorFlags exec;
};

int run_verify(const VerifyOptions& o) {
  auto model = load_model(o.model);
  if (!model.ok()) return report_error("verify", model.error());
  const Model& m = **model;
  if (!o.public_key.empty()) {
    auto key = read_public_key_file(o.public_key.c_str());
    if (!key.ok()) return report_error("verify", key.error());
    if (Status s = check_signature(m.integrity(), *key); !s.ok())
      return report_error("verify", s.error().with_context("%s", o.model.c_str()));
    std::printf("signature of %s by key %s: PASS\n", o.model.c_str(), o.public_key.c_str());
  }
  if (m.metadata().golden.empty()) {
    return report_error("verify", Error::make(ErrorCode::kInvalidState,
                                              "%s has no golden pairs to verify", o.model.c_str()));
  }
  auto exec = create_executor(m, o.exec);
  if (!exec.ok()) return report_error("verify", exec.error());
  auto report = verify::verify_golden(m, **exec);
  if (!report.ok()) return report_error("verify", report.error());
  for (const verify::PairResult& p : report->pairs) {
    const verify::OutputComparison& c = p.comparison;
    std::printf("golden pair %zu: max abs error %.4g (tolerance %.4g: %s), %s\n", p.index,
                c.max_abs_error, c.tolerance, c.rule, c.pass ? "PASS" : "FAIL");
  }
  const verify::HeadCheck& h = report->heads;
  if (h.stored) {
    std::printf("golden head outputs: max abs error %.4g (tolerance %.4g), %s\n", h.max_abs_error,
                h.tolerance, h.pass ? "PASS" : "FAIL");
  } else {
    std::printf("golden head outputs: none stored (a file from before them)\n");
  }
  std::printf("verify %s with the %s executor: %s\n", o.model.c_str(),
              executor_kind_name((*exec)->kind()), report->pass ? "PASS" : "FAIL");
  return report->pass ? kExitOk : kExitFailure;
}

}  // namespace

void add_verify_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<VerifyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "verify", "Run the model's embedded golden I/O pairs and compare (exit 1 on mismatch)");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  cmd->add_option("--public-key", o->public_key,
                  "Also require a valid signature by this key (tlvlink keygen's BASE.pub)");
  o->exec.add_to(*cmd);
  cmd->footer(std::string(kExitCodeFooter) +
              "\nTolerances: int8 outputs 1 LSB; dequantized int8 outputs 1 LSB of their scale; "
              "float models 1e-4 x the largest golden magnitude; head probabilities 1e-3 absolute "
              "(runtime/verify golden_heads.h).");
  cmd->callback([o, &exit_code] { exit_code = run_verify(*o); });
}

}  // namespace tlvlink::cli
