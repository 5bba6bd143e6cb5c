#pragma once
// `tlvlink eval` and `tlvlink heads fit` as library calls on model files.
//
//   auto reports = evaluate_files({"fp32.tlvm", "int8.tlvm"}, data, options);
//   std::fputs(format_table(pointers_to(*reports)).c_str(), stdout);    // eval.h
//
//   HeadsFitJob job{.model_path = "m.tlvm", .output_path = "m-heads.tlvm", .data = data};
//   auto fitted = fit_heads_into_file(job);  // probes + grasp head on the train split, scored
//
//   auto run = run_eval(EvalJob{.model_path = "m.tlvm", .bounds = {"sup=sup.tlvm"}, ...});

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/eval.h"
#include "tlvlink/eval/heads.h"

namespace tlvlink::eval {

// Each model evaluated on the same data; report i has model_path = paths[i]. The grasp oracle
// is estimated once (for the first model) and shared, the data being the same. Errors name the
// model ("evaluating PATH").
Result<std::vector<EvalReport>> evaluate_files(std::span<const std::string> paths,
                                               const EvalData& data, const EvalOptions& options);

// A reference model's row (e.g. a supervised upper bound) on the same data, from "LABEL=MODEL":
// its own heads when it has them (fitted like the evaluated model's, e.g. by `heads fit` on the
// same heads' set), else linear probes fitted on this data's training split.
// Errors: a spec without '=' (kInvalidArgument), the model's errors.
Result<BoundRow> evaluate_bound(const std::string& spec, const EvalData& data,
                                const EvalOptions& options);

struct EvalJob {
  std::string model_path;
  std::string compare_path;         // optional: a second model side by side
  std::vector<std::string> bounds;  // "LABEL=MODEL": reference rows (evaluate_bound)
  std::string record_path;          // optional: write a copy of the model with trust records
  bool keep_untrusted_zero_shot = false;
  EvalData data;
  EvalOptions options;
};
struct EvalRun {
  std::vector<EvalReport> reports;       // the model (with its bound rows), then the compared one
  std::vector<std::string> trust_lines;  // one per head when record_path was written
};
// `tlvlink eval`: evaluate_files for the model (+ compare), the bound rows on the first report,
// and with record_path the model's copy whose heads record the measured accuracy (trust.h).
Result<EvalRun> run_eval(const EvalJob& job);

struct HeadsFitJob {
  std::string model_path, output_path;
  EvalData data;
  EvalOptions options;  // embedder, probe fitting, text encoder
  bool add_missing_zero_shot = true;
  bool keep_untrusted_zero_shot = false;  // else dropped from the copy (trust.h)
  // Notes of fit_heads (tasks skipped and why), as they come; `tlvlink` prints them on stderr.
  std::function<void(const std::string& note)> on_note;
};
struct HeadsFitResult {
  size_t bytes = 0;  // of the written model
  FittedHeads heads;
  EvalReport score;  // the written model's heads on the test split (as the device applies them)
  std::vector<std::string> trust_lines;  // the trust record of each head, as written
};
// Fits linear probes and the grasp head on the runtime's embeddings of the train split, scores
// the copy of the model with them (model_with_heads) as the device applies them, records that
// score in its heads (model_with_trust) and writes it to output_path.
// Errors: data/model errors, no head could be fitted (kFormat), I/O.
Result<HeadsFitResult> fit_heads_into_file(const HeadsFitJob& job);

}  // namespace tlvlink::eval
