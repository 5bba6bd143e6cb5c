#pragma once
// Dataset directory probing shared by the touch and grasp extraction: format detection, whether
// the set was written by tlvlink's simulator (then its recorded split is trusted), split labels.

#include <optional>
#include <string>

#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"

namespace tlvlink::eval::internal {

inline constexpr const char* kSimRecord = "tlvlink_sim.json";

bool file_exists(const std::string& path);
bool dir_exists(const std::string& path);
std::string join(const std::string& dir, const std::string& name);

Result<TouchFormat> detect_touch_format(const std::string& dir, TouchFormat requested);
Result<GraspFormat> detect_grasp_format(const std::string& path, GraspFormat requested);

// The directory holding a dataset's tlvlink_sim.json (`path` itself, or its parent for a file).
std::string dataset_dir(const std::string& path);
// True when the dataset records the simulator's generation (tlvlink_sim.json).
bool is_generated(const std::string& path);
// The "generator" object of tlvlink_sim.json, serialised, when present.
std::optional<std::string> generator_json(const std::string& path);

// The hash split to apply: the forced one, else none for a generated set (use the recorded split),
// else the default.
std::optional<datasets::HashSplit> split_to_apply(const EvalData& data, bool generated);
std::string split_source(const std::optional<datasets::HashSplit>& split);

// Non-blank lines of a text file (0 when it cannot be read): progress totals.
int64_t count_lines(const std::string& path);
// Items of a dataset as far as its index files tell (0 = unknown), for progress only.
int64_t expected_touch_items(const std::string& dir, TouchFormat format);
int64_t expected_grasp_items(const std::string& path, GraspFormat format);

// Counts train/test items and distinct groups.
void fill_split_counts(SplitInfo& info, const std::vector<std::string>& groups,
                       const std::vector<uint8_t>& is_test);

}  // namespace tlvlink::eval::internal
