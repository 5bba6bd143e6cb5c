#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "touch_common.h is internal to tools/datasets: include its public headers instead"
#endif
// Pieces the Touch100k and Touch-and-Go writers/loaders share. Internal.

#include <string>
#include <string_view>
#include <unordered_map>

#include "tlvlink/datasets/records.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/datasets/writer.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

// "SESSION/NNNNNNNNNN.jpg", the Touch-and-Go frame key both formats use.
std::string tag_frame_key(const std::string& session, int32_t frame_index);
// Parses "SESSION/NNNNNNNNNN.jpg" (any digit count, .jpg/.jpeg/.png); false when it is not one.
bool parse_tag_frame_key(std::string_view key, std::string& session, int32_t& frame_index);

// Checks what a touch writer needs: a safe session name, frame_index >= 0, RGB images.
Status check_touch_sample(const TouchSample& sample);

// Assigns the split of a touch sample by object and insists every session stays in one split.
class TouchSplitter {
 public:
  explicit TouchSplitter(double test_fraction) : objects_(test_fraction) {}
  Result<bool> is_test(const TouchSample& sample);
  void fill(WriteSummary& summary) const;

 private:
  SplitAssigner objects_;
  std::unordered_map<std::string, bool> sessions_;
  int64_t test_sessions_ = 0;
};

// The phrases joined with ", " (Touch100k's phrase_desc).
std::string join_phrases(const std::vector<std::string>& phrases);
// phrase_desc split at commas, trimmed, empty pieces dropped.
std::vector<std::string> split_phrases(std::string_view phrase_desc);

}  // namespace tlvlink::datasets
