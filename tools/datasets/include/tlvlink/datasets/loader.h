#pragma once
// Streaming dataset loaders: next() yields one item at a time, reading its files then, so
// memory stays at one item (plus label maps of a few bytes per frame for Touch-and-Go).
// A missing or corrupt file or a malformed line skips that item and is counted in report()
// with its path (and line); next() fails only when the dataset as a whole cannot be read.

#include <cstdint>
#include <memory>
#include <string>

#include "tlvlink/datasets/records.h"
#include "tlvlink/datasets/report.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

struct LoaderOptions {
  bool load_images = true;         // false: labels/descriptions only (no image I/O at all)
  bool load_vision = true;         // also the paired camera image (vision/, video_frame, kinect)
  bool require_vision = true;      // a missing vision image skips the item (else it stays empty)
  int32_t scale_denominator = 1;   // decode JPEGs at 1/1, 1/2, 1/4 or 1/8 size
  size_t max_kept_problems = 100;  // LoadReport keeps this many in full, counts all
};
Status validate(const LoaderOptions& options);

class TouchSampleLoader {
 public:
  virtual ~TouchSampleLoader() = default;
  // Fills `out` with the next good sample; false at the end.
  virtual Result<bool> next(TouchSample& out) = 0;
  // The format's key of the sample last returned: the `img` of Touch100k, the
  // "SESSION/NNNNNNNNNN.jpg" of Touch-and-Go.
  virtual const std::string& key() const = 0;
  // The split the dataset itself records for the sample last returned (a generated Touch100k
  // set's sidecar does); Split::kAll when it records none.
  virtual Split recorded_split() const { return Split::kAll; }
  virtual LoadReport& report() = 0;
};

class GraspEpisodeLoader {
 public:
  virtual ~GraspEpisodeLoader() = default;
  virtual Result<bool> next(GraspEpisode& out) = 0;
  // "calandra_corl2017_003.h5:/0042" (HDF5) or the touch_dir (repacked).
  virtual const std::string& key() const = 0;
  virtual LoadReport& report() = 0;
};

}  // namespace tlvlink::datasets
