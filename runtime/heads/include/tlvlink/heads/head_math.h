#pragma once
// The arithmetic of a model's heads, in one place for the board, the CLI and the evaluation (the
// float operation order is part of the contract: eval's accuracies are computed with exactly
// what the board computes).
//   linear head   logits = W e + b on the raw embedding e          (W: [labels, dim])
//   zero-shot     logits = scale * M (e / |e|), |e| in double       (M: [classes, dim])
//   grasp head    p = sigmoid(w . f + b), f = the features the layout names, concatenated

#include <cstddef>
#include <cstdint>
#include <span>

namespace tlvlink::heads {

void linear_logits(std::span<const float> weight, std::span<const float> bias,
                   std::span<const float> embedding, std::span<float> logits);
void zero_shot_logits(std::span<const float> prompt_matrix, float logit_scale,
                      std::span<const float> embedding, std::span<float> logits);
// w . concat(features) + b; the features' sizes add up to weight.size() (the caller checks).
float grasp_logit(std::span<const float> weight, float bias,
                  std::span<const std::span<const float>> features);

int32_t argmax(std::span<const float> values);  // the first maximum
// Softmax of the logits into probabilities (same length), stable (max subtracted), sum in
// double; returns the top-1 index. probabilities[top] == 1 / sum exactly as infer reported it.
int32_t softmax(std::span<const float> logits, std::span<float> probabilities);
float sigmoid(float logit);

}  // namespace tlvlink::heads
