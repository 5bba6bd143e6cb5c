#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "data_cache.h is internal to tools/trainer: include its public headers instead"
#endif
// The training set in memory: every sample of the requested split decoded once, resized to the
// model input (and the teacher input) with the runtime's own resize (tools/io/preprocess.h), kept
// as uint8 HWC. The runtime later sees exactly these pixels for the same frame, so train and
// deploy preprocessing cannot drift. Normalisation ((x/255 - mean)/std) happens per batch.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/metadata.h"

namespace tlvlink::trainer {

enum class SplitChoice : uint8_t { kTrain, kTest };

struct CacheOptions {
  std::string dir;
  SplitChoice split = SplitChoice::kTrain;
  int32_t touch_height = 96, touch_width = 128;
  ResizeFilter resize = ResizeFilter::kBilinear;
  bool load_vision = true;
  int32_t vision_height = 96, vision_width = 128;
  int64_t max_samples = 0;     // > 0: stop after this many samples of the split
  size_t max_cache_bytes = 0;  // error when the images would need more
  double test_fraction = 0.2;  // hash split by session when the set has no sidecar
  unsigned threads = 2;        // decoding threads
  // A touch frame of the slot's size turned (touch_height wide, touch_width high: a DIGIT's
  // portrait frame in a landscape slot) is kept as it is, and DataCache::turned says so: the
  // sensor-view augmentation makes its views at the frame's own size, as the board sees it.
  bool keep_turned = false;
};

struct DataCache {
  int32_t height = 0, width = 0;  // touch images
  int32_t vision_height = 0, vision_width = 0;
  std::vector<uint8_t> touch;             // [n, height, width, 3]
  std::vector<uint8_t> vision;            // [n, vision_height, vision_width, 3] or empty
  std::vector<uint8_t> turned;            // per sample, 1: stored width x height = height x width
  std::vector<std::string> keys;          // Touch100k `img`
  std::vector<std::string> sentences;     // sentence_desc
  std::vector<std::string> phrase_descs;  // phrases joined with ", "
  std::vector<int32_t> material;          // class id, -1 unknown (no sidecar)
  std::vector<int32_t> hard;              // 1 hard, 0 soft, -1 unknown (no sidecar)
  std::vector<int32_t> rough;             // 1 rough, 0 smooth, -1 in between or unknown
  // The contact regression's targets (supervised.h), NaN where the sidecar records no contact
  // (no sidecar, or the frame is not in contact): ln(normal force / 1 N), friction coefficient.
  std::vector<float> log_force;
  std::vector<float> friction;
  std::string split_source;  // "sidecar" or "session hash (test fraction f)"
  // The sensor profiles the samples were recorded on (sorted; empty when the set does not say):
  // the camera views the model is trained for, recorded in the model.
  std::vector<std::string> sensors;
  std::string load_summary;  // the loader's LoadReport summary
  int64_t skipped_other_split = 0;

  int64_t size() const { return static_cast<int64_t>(keys.size()); }
  size_t touch_stride() const {
    return static_cast<size_t>(height) * static_cast<size_t>(width) * 3;
  }
  size_t vision_stride() const {
    return static_cast<size_t>(vision_height) * static_cast<size_t>(vision_width) * 3;
  }
  // FNV-1a over the keys in order: a resumed run checks it sees the same samples.
  uint64_t fingerprint() const;
};

// Errors: no data_list.json / unreadable set, no sample in the split (kInvalidArgument naming the
// directory and what was found), cache limit exceeded (kOutOfMemory with the size needed).
Result<DataCache> load_cache(const CacheOptions& options);

// Per-channel mean and std of pixel/255 over a uint8 [n, h, w, 3] block (double accumulation).
void channel_stats(const std::vector<uint8_t>& pixels, std::vector<float>& mean,
                   std::vector<float>& std);

}  // namespace tlvlink::trainer
