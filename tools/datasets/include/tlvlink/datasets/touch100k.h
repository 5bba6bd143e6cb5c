#pragma once
// Touch100k layout (TLV-Link's released format):
//   DIR/data_list.json            JSON-lines: {"img": ..., "sentence_desc": ..., "phrase_desc":
//   ...} DIR/touch/<img>               the GelSight frame (JPEG) DIR/vision/<img>              the
//   paired camera image (JPEG)
// phrase_desc is the phrases joined with ", ". The writer names images "SESSION/NNNNNNNNNN.jpg"
// (Touch-and-Go's session/frame naming) and adds DIR/tlvlink_sim_samples.jsonl (ground truth,
// one line per data_list.json line, with the sample's split: train/test never share a
// session) and DIR/tlvlink_sim.json.
//
// The loader fills TouchSample.touch, .vision, .sentence_desc and .phrases (phrase_desc split at
// commas, trimmed; a JSON array of strings is accepted too), plus .session/.frame_index when
// img looks like "SESSION/NNNNNNNNNN.jpg". Touch100k has no material labels, physics or
// contact state: those come only from the sidecar of a generated set (object_id is -1 and
// material.class_id -1 without it). Only part of the real data is public: missing images are
// counted and skipped, never replaced.

#include <memory>
#include <string>

#include "tlvlink/datasets/loader.h"
#include "tlvlink/datasets/writer.h"

namespace tlvlink::datasets {

inline constexpr const char* kTouch100kIndex = "data_list.json";
inline constexpr const char* kTouch100kSidecar = "tlvlink_sim_samples.jsonl";

// Creates DIR (and touch/, vision/); an existing data_list.json is an error (no silent mixing).
Result<std::unique_ptr<TouchDatasetWriter>> create_touch100k_writer(const std::string& dir,
                                                                    const WriterOptions& options);

struct Touch100kLoaderOptions : LoaderOptions {
  bool use_sidecar = true;  // read tlvlink_sim_samples.jsonl when present
};
Result<std::unique_ptr<TouchSampleLoader>> open_touch100k(const std::string& dir,
                                                          const Touch100kLoaderOptions& options);

}  // namespace tlvlink::datasets
