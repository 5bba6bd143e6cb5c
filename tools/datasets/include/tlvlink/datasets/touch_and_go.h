#pragma once
// Touch-and-Go layout:
//   DIR/YYYYMMDD_HHMMSS/gelsight_frame/NNNNNNNNNN.jpg   GelSight frame
//   DIR/YYYYMMDD_HHMMSS/video_frame/NNNNNNNNNN.jpg      paired camera frame
//   label files, one "SESSION/NNNNNNNNNN.jpg,<id>" per line:
//     train.txt / test.txt              material id 0..19
//     train_hard.txt / test_hard.txt    1 hard, 0 soft
//     train_rough.txt / test_rough.txt  1 rough, 0 smooth (frames in between are left out)
// The label file names are ours (TagLayout lets a loader read other names). The writer splits
// by object/session: a session's frames are all in train or all in test. It also writes
// tlvlink_sim_train.jsonl / tlvlink_sim_test.jsonl (ground truth, line for line with
// train.txt / test.txt) and tlvlink_sim.json.
//
// The loader fills TouchSample.session, .frame_index, .material.class_id, .material.hard (hard
// file, else the class rule: ids 7, 8, 9, 11, 13 soft), .material.rough (-1 when not listed),
// .touch and .vision. TAG has no descriptions, physics or contact state (only from the
// sidecar of a generated set; object_id is -1 without it). The published split is by frame
// and leaks sessions: HashSplit re-splits by session.

#include <memory>
#include <optional>
#include <string>

#include "tlvlink/datasets/loader.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/datasets/writer.h"

namespace tlvlink::datasets {

struct TagLayout {
  std::string material_train = "train.txt", material_test = "test.txt";
  std::string hard_train = "train_hard.txt", hard_test = "test_hard.txt";
  std::string rough_train = "train_rough.txt", rough_test = "test_rough.txt";
};

Result<std::unique_ptr<TouchDatasetWriter>> create_tag_writer(const std::string& dir,
                                                              const WriterOptions& options);

struct TagLoaderOptions : LoaderOptions {
  TagLayout layout;
  Split split = Split::kTrain;
  // Set: read both material files and re-split by session hash (the split files are ignored).
  std::optional<HashSplit> resplit;
  bool use_sidecar = true;
};
// Missing material files are an error; missing hard/rough files leave those labels derived
// (hard) or unknown (rough).
Result<std::unique_ptr<TouchSampleLoader>> open_touch_and_go(const std::string& dir,
                                                             const TagLoaderOptions& options);

// Parses "SESSION/NNNNNNNNNN.jpg,<id>" (trailing spaces / \r allowed); the error says why.
struct TagLabelLine {
  std::string key;  // "SESSION/NNNNNNNNNN.jpg"
  std::string session;
  int32_t frame_index = 0;
  int32_t label = 0;
};
Result<TagLabelLine> parse_tag_label_line(std::string_view line);

}  // namespace tlvlink::datasets
