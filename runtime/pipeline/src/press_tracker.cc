#include "tlvlink/pipeline/press_tracker.h"

#include <algorithm>

namespace tlvlink::pipeline {

PressTracker::PressTracker(int32_t embedding_dim)
    : dim_(static_cast<size_t>(std::max(embedding_dim, 0))),
      first_(dim_),
      recent_(kPeakRadius * dim_),
      window_(dim_),
      peak_(dim_) {}

void PressTracker::restart() { frames_ = 0; }

void PressTracker::add(std::span<const float> e, float score) {
  if (e.size() != dim_) return;  // FrameProcessor feeds the encoder's embedding only
  if (frames_ == 0) std::copy(e.begin(), e.end(), first_.begin());
  if (frames_ == 0 || score > best_score_) {
    // A new peak: its window starts with the frames before it (those this contact had).
    best_score_ = score;
    after_best_ = 0;
    const int32_t before = std::min(frames_, kPeakRadius);
    std::fill(window_.begin(), window_.end(), 0.0);
    for (int32_t b = 1; b <= before; ++b) {
      const float* r = recent_.data() + static_cast<size_t>((frames_ - b) % kPeakRadius) * dim_;
      for (size_t i = 0; i < dim_; ++i) window_[i] += static_cast<double>(r[i]);
    }
    for (size_t i = 0; i < dim_; ++i) window_[i] += static_cast<double>(e[i]);
    window_frames_ = before + 1;
  } else if (after_best_ < kPeakRadius) {
    ++after_best_;
    for (size_t i = 0; i < dim_; ++i) window_[i] += static_cast<double>(e[i]);
    ++window_frames_;
  }
  std::copy(e.begin(), e.end(),
            recent_.begin() +
                static_cast<std::ptrdiff_t>(static_cast<size_t>(frames_ % kPeakRadius) * dim_));
  ++frames_;
  for (size_t i = 0; i < dim_; ++i)
    peak_[i] = static_cast<float>(window_[i] / static_cast<double>(window_frames_));
}

}  // namespace tlvlink::pipeline
