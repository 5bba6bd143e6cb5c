#pragma once
// `tlvlink eval` and `tlvlink heads fit` as library calls on model files.
//
//   auto reports = evaluate_files({"fp32.tlvm", "int8.tlvm"}, data, options);
//   std::fputs(format_table(pointers_to(*reports)).c_str(), stdout);    // eval.h
//
//   HeadsFitJob job{.model_path = "m.tlvm", .output_path = "m-heads.tlvm", .data = data};
//   auto fitted = fit_heads_into_file(job);  // probes + grasp head on the train split, scored

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

struct HeadsFitJob {
  std::string model_path, output_path;
  EvalData data;
  EvalOptions options;  // embedder, probe fitting, text encoder
  bool add_missing_zero_shot = true;
  // Notes of fit_heads (tasks skipped and why), as they come; `tlvlink` prints them on stderr.
  std::function<void(const std::string& note)> on_note;
};
struct HeadsFitResult {
  size_t bytes = 0;      // of the written model
  FittedHeads heads;
  EvalReport score;      // the written model's heads on the test split (as the device applies them)
};
// Fits linear probes and the grasp head on the runtime's embeddings of the train split, writes
// a copy of the model with them (model_with_heads) to output_path, and scores what was written.
// Errors: data/model errors, no head could be fitted (kFormat), I/O.
Result<HeadsFitResult> fit_heads_into_file(const HeadsFitJob& job);

}  // namespace tlvlink::eval
