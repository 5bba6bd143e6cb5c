#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "meta.h is internal to tools/datasets: include its public headers instead"
#endif
// The simulator's ground truth per item as JSON (tlvlink_sim_*.jsonl sidecars, the HDF5
// `tlvlink_sim` attribute), both ways, and the lock-step sidecar reader. Internal.

#include <nlohmann/json.hpp>

#include <string>

#include "line_io.h"
#include "tlvlink/datasets/records.h"
#include "tlvlink/datasets/report.h"

namespace tlvlink::datasets {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

// Parses one JSON text; false with the parser's reason.
bool parse_json(const std::string& text, Json& out, std::string& why);

OrderedJson touch_meta(const TouchSample& sample, const std::string& key, bool test);
OrderedJson grasp_meta(const GraspEpisode& episode, const std::string& key, bool test);
// Fill the simulator fields (object id, material, contact / variables, states) from metadata;
// false with the reason when a field is missing, of the wrong type or out of range (a material
// class_id outside 0..kMaterialClassCount-1; -1, "unlabelled", is what writers store for an
// unknown class). On false `out` may be partly filled: the caller drops the item.
bool apply_touch_meta(const Json& meta, TouchSample& out, std::string& why);
bool apply_grasp_meta(const Json& meta, GraspEpisode& out, std::string& why);

// Reads a sidecar line for line with its index file. Absent file: inactive, no problem.
// A line whose "key" differs from the index's, or a malformed line, is reported once as
// kSidecarMismatch and the reader stops (metadata is then left at its defaults).
class SidecarReader {
 public:
  void open(const std::string& path);
  bool active() const { return active_; }
  // The metadata of the next index line (key must match), or nullptr.
  const Json* next(const std::string& key, LoadReport& report);
  // Advances past the line of an index line that was itself unusable.
  void skip();
  // The sidecar and the line next() last returned, for file:line problems.
  const std::string& path() const { return reader_.path(); }
  int64_t line_number() const { return reader_.line_number(); }

 private:
  void stop(const std::string& why, LoadReport& report);
  LineReader reader_;
  Json current_;
  bool active_ = false;
};

}  // namespace tlvlink::datasets
