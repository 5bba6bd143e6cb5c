#pragma once
// What a board's outputs call things: sensors, the model's per-frame heads with their labels and
// trust records, the grasp head. Resolved once at start from the heads a model's evaluator holds;
// the Hello and the JSON lines name their fields from it.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tlvlink/heads/evaluator.h"

namespace tlvlink::stream {

struct OutputNames {
  std::vector<std::string> sensors;
  struct Head {
    std::string name, kind;
    std::vector<std::string> labels;
    // The model's trust record (metadata.h HeadTrust), NaN when the head has none.
    float accuracy = std::numeric_limits<float>::quiet_NaN();
    float majority = std::numeric_limits<float>::quiet_NaN();
    // Cross-validated records (`heads fit --images`), NaN / 0 when the head has none.
    float ci_low = std::numeric_limits<float>::quiet_NaN();
    float ci_high = std::numeric_limits<float>::quiet_NaN();
    float balanced = std::numeric_limits<float>::quiet_NaN();
    float baseline = std::numeric_limits<float>::quiet_NaN();
    uint32_t groups = 0;
  };
  std::vector<Head> heads;  // in FramePrediction::heads[].head index order (all per-frame heads)
  std::string grasp_head;
  Head grasp;  // the grasp head's trust record (name and labels unused)
};

// The names of `heads`' per-frame heads (and of grasp head `grasp_head`, the one the board uses:
// pipeline::FrameProcessor::grasp_head()) for sensors named `sensors`.
OutputNames output_names(std::vector<std::string> sensors, const heads::HeadEvaluator& heads,
                         size_t grasp_head = 0);

}  // namespace tlvlink::stream
