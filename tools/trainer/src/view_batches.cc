// Prefetched, augmented training batches.

#include "view_batches.h"

#include <memory>
#include <utility>

#include "augment_rng.h"

namespace tlvlink::trainer {

Result<std::unique_ptr<ViewBatches>> ViewBatches::create(const DataCache& cache,
                                                         const TrainOptions& o,
                                                         const InputSpec& model_input) {
  TLV_ENSURE(cache.height == o.view.frame_height && cache.width == o.view.frame_width,
             ErrorCode::kInvalidState,
             "view augmentation: the cache holds %dx%d frames, the views are made at %dx%d",
             cache.width, cache.height, o.view.frame_width, o.view.frame_height);
  std::unique_ptr<ViewBatches> batches(new ViewBatches());
  ViewBatches& b = *batches;
  b.cache_ = &cache;
  b.seed_ = o.seed;
  b.components_ = o.view.components;
  b.views_ = o.view.consistency_weight > 0 ? 2 : 1;
  b.codec_pairs_ = o.view.codec_pairs;
  b.model_bytes_ =
      static_cast<size_t>(model_input.height) * static_cast<size_t>(model_input.width) * 3;
  TLV_ASSIGN_OR_RETURN(ViewAugmenter a,
                       ViewAugmenter::create(cache.width, cache.height, model_input));
  b.augmenter_ = std::make_unique<ViewAugmenter>(std::move(a));
  TLV_ASSIGN_OR_RETURN(ViewAugmenter t,
                       ViewAugmenter::create(cache.height, cache.width, model_input,
                                             image::Orientation::kTransposed));
  b.turned_ = std::make_unique<ViewAugmenter>(std::move(t));
  return batches;
}

ViewBatches::~ViewBatches() {
  if (pending_.valid()) pending_.wait();
}

Status ViewBatches::make(int64_t step, const std::vector<int64_t>& idx, std::vector<uint8_t>& out) {
  out.resize(static_cast<size_t>(views_) * idx.size() * model_bytes_);
  const size_t stride = cache_->touch_stride();
  for (int32_t v = 0; v < views_; ++v) {
    for (size_t i = 0; i < idx.size(); ++i) {
      const auto sample = static_cast<size_t>(idx[i]);
      const std::span<const uint8_t> frame(cache_->touch.data() + sample * stride, stride);
      const size_t slot = static_cast<size_t>(v) * idx.size() + i;
      const bool turned = sample < cache_->turned.size() && cache_->turned[sample] != 0;
      ViewAugmenter& augmenter = turned ? *turned_ : *augmenter_;
      const std::span<uint8_t> view(out.data() + slot * model_bytes_, model_bytes_);
      const uint64_t seed = view_seed(seed_, step, idx[i], v);
      if (v == 1 && codec_pair(step, idx[i])) {
        TLV_TRY(augmenter.make_codec_twin(frame, components_, view_seed(seed_, step, idx[i], 0),
                                          seed, view));
      } else {
        TLV_TRY(augmenter.make(frame, components_, seed, view));
      }
    }
  }
  return {};
}

bool ViewBatches::codec_pair(int64_t step, int64_t sample) const {
  if (codec_pairs_ <= 0) return false;
  uint64_t state =
      view_seed(seed_, step, sample, 2);  // a stream of its own: views 0, 1 keep theirs
  return rng::chance(state, codec_pairs_);
}

void ViewBatches::request(int64_t step, std::vector<int64_t> idx) {
  if (pending_.valid()) pending_.wait();
  filling_ ^= 1;
  std::vector<uint8_t>& out = buffers_[filling_];
  pending_ = std::async(std::launch::async,
                        [this, step, idx = std::move(idx), &out] { return make(step, idx, out); });
}

Result<const std::vector<uint8_t>*> ViewBatches::take() {
  TLV_ENSURE(pending_.valid(), ErrorCode::kInvalidState, "no training batch was requested");
  TLV_TRY(pending_.get());
  return &buffers_[filling_];
}

}  // namespace tlvlink::trainer
