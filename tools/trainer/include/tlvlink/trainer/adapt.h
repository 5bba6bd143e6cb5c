#pragma once
// Does adapting the encoder to a user's own frames pay, beyond a linear head? (issue 30 item 7)
// The last conv layer(s) and the FC of the checkpoint a model was exported from are fine-tuned
// with a classifier on the user's labelled frames, inside the same grouped folds that score the
// linear head (tools/eval grouped_cv.h), and both are scored on the groups each fold did not see.
// Only the comparison is produced: a model is written only by the commands that exist for it
// (train -> export -> heads fit -> quantize) once the comparison says it pays.
//
//   AdaptOptions o{.checkpoint = "tiny.ckpt"};
//   auto r = compare_adapted_head(model, frames, "", o);   // model exported from tiny.ckpt
//   // r->linear.accuracy vs r->adapted.accuracy, with 95 % intervals, on the same folds

#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/model.h"

namespace tlvlink::trainer {

struct AdaptOptions {
  std::string checkpoint;  // the `tlvlink train` checkpoint `model` was exported from
  int32_t layers = 1;      // conv layers adapted, counted from the last (the FC always is)
  int32_t steps = 150;     // full-batch AdamW steps per fold (0: the linear head itself)
  float lr = 1e-4f;        // small: the start is the linear head's solution, kept near it
  float weight_decay = 1e-4f;
  int32_t folds = 5;  // at most (grouped_cv.h: fewer when a class has fewer groups)
  uint64_t seed = 0;
  int32_t threads = 1;
};

struct HeadScore {
  double accuracy = 0, ci_low = 0, ci_high = 0, balanced_accuracy = 0;
};

struct AdaptComparison {
  int64_t n = 0, groups = 0;
  int32_t folds = 0, classes = 0, steps = 0;
  double majority = 0;
  HeadScore linear;   // linear head on the frozen encoder (what `heads fit --images` records)
  HeadScore adapted;  // the adapted layers + classifier, same folds
  int64_t adapted_only_right = 0, linear_only_right = 0;  // paired rows
  // Cross-entropy on the fitting rows at the first and after the last step (mean over folds):
  // that the adaptation fits them better is what it can promise, not that it generalises.
  double fit_loss_start = 0, fit_loss_end = 0;
  // The checkpoint's encoder against the model's fp32 graph on these frames: the smallest
  // cosine (the comparison is refused below 0.999: they are not the same encoder).
  double encoder_cosine = 0;
  std::string trained;  // "conv 5 (64 -> 128) + FC: 12.3 k of 310 k parameters"
  double seconds = 0;
};

// Errors: checkpoint unreadable or not the one `model` came from (cosine named), options out of
// range, frames from recordings (images only), and every error of grouped cross-validation
// (a class with fewer than two groups ...).
Result<AdaptComparison> compare_adapted_head(const Model& model, const eval::LabelledFrames& frames,
                                             const std::string& sensor,
                                             const AdaptOptions& options);

// The comparison as the CLI prints it, with the verdict (pays only when the adapted head's
// accuracy is above the linear head's and its interval's low end above the linear accuracy).
std::string format_adapt_comparison(const AdaptComparison& c, const std::string& head);

}  // namespace tlvlink::trainer
