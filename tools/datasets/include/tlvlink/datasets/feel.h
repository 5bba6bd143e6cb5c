#pragma once
// "The Feeling of Success" (Feel) grasp dataset, in two layouts.
//
// HDF5 (the published files): DIR/calandra_corl2017_NNN.h5, records_per_file grasps each.
// One group per grasp record at the root, named "0000", "0001", ... (the loader reads every
// root group, whatever its name, in name order). Each record group holds the documented keys:
//   object_name                 scalar variable-length UTF-8 string
//   is_gripping                 scalar uint8, 1 = still held after the lift
//   gelsightA_{before,during,after}, gelsightB_{...}, kinectA_rgb_{...}
//                               uint8 datasets H x W x 3 (chunked, deflate)
// and an attribute `tlvlink_sim` (a JSON string: object id, split, material, grasp variables
// incl. the hidden mass / centre-of-mass offset / lift acceleration, contact states) when the
// file was generated. The published GelSight frames are stored rotated: the writer can rotate
// them by quarter turns (gelsight_quarter_turns) and the loader turns them back by as many.
//
// Repacked (TLV-Link's layout):
//   DIR/data/<touch_dir>/gelsight{A,B}_{before,during,after}.jpg
//   DIR/train_info.json, DIR/test_info.json   JSON-lines {"object", "touch_dir", "grasping"}
// touch_dir is "<object_name>_<NNNNNN>" (episode number); plus tlvlink_sim_{train,test}.jsonl
// (line for line with the info files) and tlvlink_sim.json.
//
// Both writers split by object (train/test never share an object). The loaders fill
// GraspEpisode.object_name, .is_gripping and .frames; HDF5 also .vision (kinectA_rgb). The
// variables, material and object_id come only from tlvlink_sim metadata (object_id -1 without).

#include <memory>
#include <optional>
#include <string>

#include "tlvlink/datasets/loader.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/datasets/writer.h"

namespace tlvlink::datasets {

struct FeelWriterOptions : WriterOptions {
  int32_t records_per_file = 100;  // [1, 10000] grasps per calandra_corl2017_NNN.h5
  int32_t deflate_level = 1;       // [0, 9]; 0 stores the arrays uncompressed
  // > 0: JPEG round trip at this quality before storing the HDF5 arrays (the rig's MJPEG
  // camera); the repacked writer then compresses a second time at jpeg_quality (Feel-like
  // double compression with both at ~95).
  int32_t camera_jpeg_quality = 0;  // 0 or [1, 100]
  // The GelSight frames already went through their camera's raw output and the board's decoder
  // (sim::GraspSetOptions::live_path): camera_jpeg_quality then applies to the vision frames only.
  bool gelsight_live_path = false;
  int32_t gelsight_quarter_turns = 0;  // [0, 3] counterclockwise, HDF5 only
};

Result<std::unique_ptr<GraspDatasetWriter>> create_feel_writer(const std::string& dir,
                                                               const FeelWriterOptions& options);
Result<std::unique_ptr<GraspDatasetWriter>> create_feel_repacked_writer(
    const std::string& dir, const FeelWriterOptions& options);

struct FeelLoaderOptions : LoaderOptions {
  Split split = Split::kAll;
  // Set: split by object-name hash. Unset: the recorded split (HDF5: the tlvlink_sim attribute,
  // records without one are counted as malformed when a split is asked for; repacked: the
  // {train,test}_info.json files).
  std::optional<HashSplit> resplit;
  int32_t gelsight_quarter_turns = 0;  // [0, 3] clockwise, undoing the writer's rotation
  bool use_sidecar = true;             // repacked: read tlvlink_sim_{train,test}.jsonl
};

// DIR holding calandra_corl2017_*.h5, or one such file. A file that cannot be opened (missing,
// truncated, not HDF5) is counted as corrupt with HDF5's reason and loading goes on.
Result<std::unique_ptr<GraspEpisodeLoader>> open_feel(const std::string& path,
                                                      const FeelLoaderOptions& options);
Result<std::unique_ptr<GraspEpisodeLoader>> open_feel_repacked(const std::string& dir,
                                                               const FeelLoaderOptions& options);

}  // namespace tlvlink::datasets
