#pragma once
#ifndef TLVLINK_SCORE_PRIVATE
#error "predictions.h is internal to tools/score: include its public headers instead"
#endif
// A run's predictions as the scorer needs them, from either side of the stream: the JSON lines a
// board writes (tlvlinkd's `jsonl:` output) or `tlvlink listen --json` (the same form:
// runtime/stream json_lines.h — hello, frame_prediction, grasp_prediction), and tlvlinkd's lines
// of before protocol 1.3 (type frame / grasp, sensors and heads by name), which users keep.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::score::internal {

enum class Gate { kCalibrating, kNone, kContact };

struct FrameRecord {
  int32_t finger = -1;  // 0 = A, 1 = B; -1 = a sensor that is neither
  int64_t seq = -1;     // the camera's frame sequence
  Gate gate = Gate::kNone;
  bool encoded = false;  // the encoder ran
  // Per head that ran: its name and top label (lower-case).
  std::vector<std::pair<std::string, std::string>> labels;
};

struct GraspRecord {
  bool computed = false;
  std::string reason;         // why not, when not computed
  int64_t during_seq_a = -1;  // finger A's "during" frame, -1 when not named
  bool success = false;       // predicted success (p >= 0.5)
};

// Calls `frame` / `grasp` per record of `path`, in file order; `fingers` names the sensors of
// finger A and B. Errors name the file and line.
Status read_predictions(const std::string& path, const std::vector<std::string>& fingers,
                        const std::function<Status(const FrameRecord&)>& frame,
                        const std::function<Status(const GraspRecord&)>& grasp);

}  // namespace tlvlink::score::internal
