#pragma once
#ifndef TLVLINK_SCORE_PRIVATE
#error "truth.h is internal to tools/score: include its public headers instead"
#endif
// The scenario's ground truth (truth.jsonl) and the JSON-lines reader, shared by the scorer and
// the live/offline comparison. Internal to tools/score.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/io/line_reader.h"

namespace tlvlink::score::internal {

using nlohmann::json;

struct TruthFrame {
  bool contact = false;
  double force_n = 0;
  // What the optics show: the largest block-mean difference from the open gel, DN (scenarios
  // before it was recorded: taken as visible).
  double signal_dn = 1e9;
  int32_t event = -1;
};

struct TruthEvent {
  std::string kind;
  bool has_success = false, success = false;
  std::map<std::string, std::string> labels;  // head -> label ("" when undefined)
};

struct Truth {
  int64_t frames = 0;
  std::vector<TruthFrame> fingers[2];
  std::vector<TruthEvent> events;
};

std::string lower(std::string s);

// Reads a JSON-lines file, calling `each` per object; errors name the file and line.
template <typename Each>
Status read_lines(const std::string& path, Each each) {
  tools::LineReader in;
  TLV_TRY(in.open(path));
  std::string line;
  while (in.next(line)) {
    const int64_t n = in.line_number();
    TLV_ENSURE(!in.too_long(), ErrorCode::kFormat, "%s:%lld: line longer than %zu bytes",
               path.c_str(), static_cast<long long>(n), tools::kMaxLineBytes);
    if (line.empty()) continue;
    json j = json::parse(line, nullptr, false);
    TLV_ENSURE(!j.is_discarded() && j.is_object(), ErrorCode::kFormat, "%s:%lld: not a JSON object",
               path.c_str(), static_cast<long long>(n));
    Status st = each(j);
    if (!st.ok())
      return st.error().with_context("%s:%lld", path.c_str(), static_cast<long long>(n));
  }
  return in.error();
}

Result<Truth> read_truth(const std::string& path);

// The scripted grasp a grasp record belongs to: the event of finger A's "during" frame
// (`during_seq_a`); -1 when the record names none (-1) or it falls outside every grasp.
int32_t grasp_event(int64_t during_seq_a, const Truth& truth);

}  // namespace tlvlink::score::internal
