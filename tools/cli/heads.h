#pragma once
// Turning an embedding into head predictions (linear probes, zero-shot), for `infer`'s summary.

#include <span>
#include <string>
#include <vector>

#include "tlvlink/metadata.h"

namespace tlvlink::cli {

struct HeadPrediction {
  std::string head;
  const char* kind = "probe";  // "probe" (linear head) or "zero-shot" (prompt matrix)
  std::string label;      // top-1
  float probability = 0;  // softmax over the head's logits
  std::vector<float> logits;
};

// One prediction per linear and zero-shot head (the grasp head needs several embeddings).
std::vector<HeadPrediction> predict_heads(const Metadata& metadata,
                                          std::span<const float> embedding);

}  // namespace tlvlink::cli
