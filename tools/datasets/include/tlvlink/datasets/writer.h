#pragma once
// Streaming dataset writers: samples go in one at a time and are written out at once (images
// as files, one index line each), so a 100k-sample set never sits in memory. finish() closes
// the index files and writes `tlvlink_sim.json` (format, generator options and seed, writer
// options, counts). Every writer also writes the simulator's ground truth (material physics,
// contact state, grasp variables) to `tlvlink_sim_<index>.jsonl` sidecars in the same order as
// the format's own index files, which stay exactly in the real format.

#include <cstdint>
#include <memory>
#include <string>

#include "tlvlink/datasets/records.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

struct WriterOptions {
  int32_t jpeg_quality = 90;  // [1, 100], every JPEG the writer stores
  // Store touch frames' JPEGs 4:4:4 instead of 4:2:0: the colour detail where a GelSight shows
  // fine surface normals is kept (with quality 100 the frames are within a few DN).
  bool jpeg_full_chroma = false;
  double test_fraction = 0.2;         // [0, 1], share of sessions/objects in the test split
  std::string generator_json = "{}";  // JSON object describing what made the samples
                                      // (e.g. sim::touch_set_options_json()); in tlvlink_sim.json
  bool sidecar = true;                // write the tlvlink_sim_*.jsonl ground-truth sidecars
};
Status validate(const WriterOptions& options);

struct WriteSummary {
  int64_t items = 0;  // samples or episodes written
  int64_t train_items = 0, test_items = 0;
  int64_t objects = 0, test_objects = 0;  // sessions (touch) or objects (grasp)
  int64_t files = 0;                      // files created (images, HDF5, index files)
  int64_t bytes = 0;                      // bytes written
};

class TouchDatasetWriter {
 public:
  virtual ~TouchDatasetWriter() = default;
  // Writes one sample. Sample images must be non-empty RGB (height * width * 3 bytes).
  virtual Status write(const TouchSample& sample) = 0;
  // Closes the index files and writes tlvlink_sim.json; nothing may be written afterwards.
  virtual Status finish() = 0;
  virtual const WriteSummary& summary() const = 0;
};

class GraspDatasetWriter {
 public:
  virtual ~GraspDatasetWriter() = default;
  virtual Status write(const GraspEpisode& episode) = 0;
  virtual Status finish() = 0;
  virtual const WriteSummary& summary() const = 0;
};

}  // namespace tlvlink::datasets
