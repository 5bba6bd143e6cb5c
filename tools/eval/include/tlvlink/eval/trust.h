#pragma once
// Trust records written into a model from an evaluation (the model file's HeadTrust, read back
// by runtime/heads/include/tlvlink/head_trust.h): each head gets the test accuracy its cell of the
// report measured ("model's heads" for linear and grasp heads, "zero-shot" for zero-shot heads),
// the test split's majority-class rate and a description of the set. `tlvlink heads fit` and
// `tlvlink eval --record` write them.
//
//   auto report = evaluate(model, data, options);
//   auto bytes = model_with_trust(model, *report, {}, &lines);   // same graph, new metadata

#include <cstddef>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/eval.h"
#include "tlvlink/eval/grouped_cv.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::eval {

struct TrustRecordOptions {
  // Zero-shot heads whose record says they do not beat the majority class (head_trust.h's rule)
  // are removed from the copy: a zero-shot head is optional (the task's linear head stays), and
  // one that guesses no better than chance only misleads.
  bool drop_untrusted_zero_shot = true;
};

// The record as the runtime reads it (string views into `spec`), for head_trust.h's rule.
HeadTrust trust_view(const quantize::HeadTrustSpec& spec);

// The record of a head validated by grouped cross-validation beside a baseline on the same folds
// (`heads fit --images`, `--presses`): accuracy, interval, balanced accuracy, majority, groups,
// n (rows) and the baseline's accuracy and name; the caller describes the test set.
// The one line `heads fit` prints for a head it wrote: "head 'NAME' (added|replaced) LEVEL: why,
// reported by default | left out of the default output"; `below_baseline` says why when the
// record's baseline did at least as well (e.g. "it does not beat the pixel baseline, ").
std::string trust_decision_line(const std::string& head, bool replaced,
                                const quantize::HeadTrustSpec& trust,
                                const std::string& below_baseline);

quantize::HeadTrustSpec cross_validated_trust(const CvResult& head, const CvResult& baseline,
                                              const std::string& baseline_name);

// "touch: DIR (touch100k) test split (recorded): 2400 items, 300 groups"
std::string test_set_description(const EvalReport& report, Task task);

// A copy of `model` (same graph, constants, golden pairs) whose heads carry the report's figures.
// A head the report did not score keeps the record it had. `lines` (optional) receives one
// human-readable line per head: name, accuracy, majority, n, decision. Errors: the copy does not
// load.
Result<std::vector<std::byte>> model_with_trust(const Model& model, const EvalReport& report,
                                                const TrustRecordOptions& options,
                                                std::vector<std::string>* lines = nullptr);

}  // namespace tlvlink::eval
