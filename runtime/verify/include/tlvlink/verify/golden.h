#pragma once
// The golden input/output pairs a model carries, run on an executor and compared with the
// rule of compare.h: `tlvlink verify`, the board smoke test and the daemon's start-up self-test.

#include <cstddef>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "tlvlink/verify/compare.h"
#include "tlvlink/verify/golden_heads.h"

namespace tlvlink::verify {

struct PairResult {
  size_t index = 0;
  OutputComparison comparison;
};

struct GoldenReport {
  std::vector<PairResult> pairs;
  HeadCheck heads;    // the stored head outputs (golden_heads.h); heads.stored false: none
  bool pass = false;  // every pair within tolerance, and the heads
};

// Runs every golden pair through `executor` (created for `model`), then checks the stored head
// outputs (golden_heads.h: on the stored embeddings, so independent of the executor). Errors: no
// golden pairs (kInvalidState), a pair whose sizes differ from the graph's (kModelInvalidMetadata),
// a failed invoke (with "golden pair N" as context). A mismatch is not an error: report.pass is
// false.
Result<GoldenReport> verify_golden(const Model& model, Executor& executor);

}  // namespace tlvlink::verify
