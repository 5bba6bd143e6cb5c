#pragma once
#ifndef TLVLINK_TRAINER_PRIVATE
#error "view_batches.h is internal to tools/trainer: include its public headers instead"
#endif
// The touch frames of a training step under the sensor-view augmentation, each made at the
// frame's own size and orientation (DataCache::turned), made on a worker
// thread while the previous step trains (a libtorch step holds one core; this the other). No
// libtorch. Every view is a function of (run seed, step, sample, view), so prefetching changes
// no result and a resumed run draws what an uninterrupted one would.

#include <cstdint>
#include <future>
#include <memory>
#include <vector>

#include "data_cache.h"
#include "tlvlink/error.h"
#include "tlvlink/trainer/trainer.h"
#include "view_augment.h"

namespace tlvlink::trainer {

class ViewBatches {
 public:
  // `cache` holds frames at options.view's frame size and must outlive this; `model_input` is
  // the model's input (its size and resize filter). views: 1, or 2 with a consistency weight.
  static Result<std::unique_ptr<ViewBatches>> create(const DataCache& cache,
                                                     const TrainOptions& options,
                                                     const InputSpec& model_input);
  ViewBatches(const ViewBatches&) = delete;  // its worker points at it
  ViewBatches& operator=(const ViewBatches&) = delete;
  ~ViewBatches();

  int32_t views() const { return views_; }
  // Starts the batch of `step` (samples `idx`) in the background; one request at a time.
  void request(int64_t step, std::vector<int64_t> idx);
  // Waits for the requested batch: views() x idx.size() model inputs [h, w, 3] uint8, view 0 of
  // every sample first. Valid until the next request.
  Result<const std::vector<uint8_t>*> take();

 private:
  ViewBatches() = default;
  Status make(int64_t step, const std::vector<int64_t>& idx, std::vector<uint8_t>& out);
  // Whether the sample's second view at `step` is its first view's codec twin.
  bool codec_pair(int64_t step, int64_t sample) const;

  const DataCache* cache_ = nullptr;
  uint64_t seed_ = 0;
  uint32_t components_ = 0;
  int32_t views_ = 1;
  double codec_pairs_ = 0;  // ViewAugmentOptions::codec_pairs
  size_t model_bytes_ = 0;
  // Used by one worker at a time: the slot's orientation and, for turned frames (a DIGIT's
  // portrait frame in a landscape slot), the other.
  std::unique_ptr<ViewAugmenter> augmenter_, turned_;
  std::vector<uint8_t> buffers_[2];
  int32_t filling_ = 0;
  std::future<Status> pending_;
};

}  // namespace tlvlink::trainer
