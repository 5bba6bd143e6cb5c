#pragma once
// The heads' part of the golden pairs: every per-frame head's probabilities on each golden
// output read as the embedding, each grasp head's p(success) with golden output k as its
// layout's feature k, and the press heads' probabilities on golden outputs 0 and 1. Computed once
// here, by the writer (to store them) and by verify (to check them), with the board's own head
// arithmetic (runtime/heads).
//
// Tolerance kHeadTolerance, absolute on probabilities: the stored and the recomputed values come
// from the same float operations in the same order on the same stored embedding; only a compiler
// contracting multiply-adds (FMA, e.g. on aarch64) or another libm expf changes them, by
// at most ~dim x 2^-24 x |logit| on a logit (7.6e-4 at dim 128 and a zero-shot logit of 100),
// moving a probability by at most half the spread of the logit errors (softmax's slope) plus a
// few ulp of expf: 1e-3 bounds that with margin; a weight, bias, scale or label order that
// changes a prediction moves a probability by far more.

#include <cstddef>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/model.h"

namespace tlvlink::verify {

inline constexpr double kHeadTolerance = 1e-3;

struct GoldenHeadOutputs {
  // Per golden pair: the probabilities of every linear head then every zero-shot head.
  std::vector<std::vector<float>> pairs;
  bool has_grasp = false;
  float grasp = 0;
  // The same for each sensor grasp head, in file order (the same features).
  std::vector<float> sensor_grasp;
  // Every press head's probabilities, head after head, with golden output 0 as the press's peak
  // and golden output 1 (0 with one pair) as its first frame (metadata.h golden_press).
  std::vector<float> press;
};

// Whether the model's golden pairs can carry head outputs: golden pairs, at least one head, and
// the embedding is graph output 0 (the output golden pairs store).
bool golden_heads_apply(const Model& model);

// The head outputs on the model's golden outputs (empty `pairs` when !golden_heads_apply).
// Errors: a head whose shapes disagree with the embedding (kModelInvalidMetadata).
Result<GoldenHeadOutputs> golden_head_outputs(const Model& model);

struct HeadCheck {
  bool stored = false;       // the file stores head outputs (files from before them do not)
  double max_abs_error = 0;  // over every stored probability and the grasp value
  double tolerance = kHeadTolerance;
  bool pass = true;
};

// Recomputes the head outputs and compares them with those the file stores.
Result<HeadCheck> check_golden_heads(const Model& model);

}  // namespace tlvlink::verify
