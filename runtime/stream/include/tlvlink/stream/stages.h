#pragma once
// The stages a FramePrediction's stage_ns carries, in this order (named in the Hello): the
// latency stages a board reports up to the heads. There is no "gate" stage: the contact gate has
// no timestamp of its own (its microseconds are in "queue").

#include <array>

namespace tlvlink::stream {

inline constexpr std::array<const char*, 6> kStageNames = {"dequeue",    "decode",  "queue",
                                                           "preprocess", "encoder", "heads"};

}  // namespace tlvlink::stream
