#include <cstring>

#include "tlvlink/verify/golden.h"

namespace tlvlink::verify {

Result<GoldenReport> verify_golden(const Model& model, Executor& exec) {
  const Metadata& m = model.metadata();
  TLV_ENSURE(!m.golden.empty(), ErrorCode::kInvalidState,
             "the model has no golden pairs to verify");
  const Graph& g = model.graph();
  GoldenReport report;
  report.pass = true;
  for (size_t i = 0; i < m.golden.size(); ++i) {
    const GoldenPair& pair = m.golden[i];
    TLV_ENSURE(
        pair.input.size() == exec.input(0).size() && pair.output.size() == exec.output(0).size(),
        ErrorCode::kModelInvalidMetadata,
        "golden pair %zu: %zu input and %zu output bytes; the graph has %zu and %zu", i,
        pair.input.size(), pair.output.size(), exec.input(0).size(), exec.output(0).size());
    std::memcpy(exec.input(0).data(), pair.input.data(), pair.input.size());
    if (Status s = exec.invoke(); !s.ok()) return s.error().with_context("golden pair %zu", i);
    PairResult r{i, compare_output_bytes(g, g.outputs[0], exec.output(0), pair.output)};
    report.pass = report.pass && r.comparison.pass;
    report.pairs.push_back(r);
  }
  TLV_ASSIGN_OR_RETURN(report.heads, check_golden_heads(model));
  report.pass = report.pass && report.heads.pass;
  return report;
}

}  // namespace tlvlink::verify
