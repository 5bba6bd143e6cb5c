#pragma once
// Two executors' outputs on the same input, compared output by output with the rule of
// compare.h: `tlvlink infer --compare-executors` (XNNPACK against the reference).

#include <vector>

#include "tlvlink/executor.h"
#include "tlvlink/model.h"
#include "tlvlink/verify/compare.h"

namespace tlvlink::verify {

struct ExecutorComparison {
  std::vector<OutputComparison> outputs;  // one per graph output, in order
  bool pass = false;                      // every output within tolerance
};

// `got` and `want` were created for `model` and have both been invoked on the same inputs.
ExecutorComparison compare_executors(const Model& model, const Executor& got, const Executor& want);

}  // namespace tlvlink::verify
