#pragma once
#ifndef TLVLINK_EVAL_PRIVATE
#error "data_paths.h is internal to tools/eval: include its public headers instead"
#endif
// Dataset directory probing shared by the touch and grasp extraction. Format detection and the
// split rule are tools/datasets' (tlvlink/datasets/detect.h); this maps them onto EvalData's
// formats and adds what only the reports need (split source text, progress totals).

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "tlvlink/datasets/records.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/sim/live_path.h"

namespace tlvlink::eval::internal {

bool file_exists(const std::string& path);
bool dir_exists(const std::string& path);
std::string join(const std::string& dir, const std::string& name);

// `requested` when given (the path must exist), else datasets::detect_dataset_format, which must
// name a format of the right kind.
Result<TouchFormat> detect_touch_format(const std::string& dir, TouchFormat requested);
Result<GraspFormat> detect_grasp_format(const std::string& path, GraspFormat requested);
datasets::DatasetFormat dataset_format(TouchFormat format);
datasets::DatasetFormat dataset_format(GraspFormat format);

// The "generator" object of tlvlink_sim.json, serialised, when present.
std::optional<std::string> generator_json(const std::string& path);

// datasets::split_to_apply with the data's forced and default splits.
std::optional<datasets::HashSplit> split_to_apply(const EvalData& data, const std::string& path,
                                                  datasets::DatasetFormat format);
std::string split_source(const std::optional<datasets::HashSplit>& split);

// The frame saved as a JPEG at `quality` (4:2:0, as datasets and tools save) and read back: the
// codec path of stability.h and of EvalData::train_jpeg_qualities.
Result<datasets::RgbImage> jpeg_path(const datasets::RgbImage& frame, int32_t quality);

// The frame through its sensor's live path (sim::LivePath: the camera's raw output and the
// board's decoder), in place: the live path of stability.h and of EvalData::train_live_path.
// One LivePath per sensor profile, made on first use.
class LivePaths {
 public:
  Status apply(const std::string& sensor, std::span<uint8_t> rgb);

 private:
  std::map<std::string, std::unique_ptr<sim::LivePath>> paths_;
};

// Non-blank lines of a text file (0 when it cannot be read): progress totals.
int64_t count_lines(const std::string& path);
// Items of a dataset as far as its index files tell (0 = unknown), for progress only.
int64_t expected_touch_items(const std::string& dir, TouchFormat format);
int64_t expected_grasp_items(const std::string& path, GraspFormat format);

// Counts train/test items and distinct groups.
void fill_split_counts(SplitInfo& info, const std::vector<std::string>& groups,
                       const std::vector<uint8_t>& is_test);

}  // namespace tlvlink::eval::internal
