#pragma once
// One sensor's press as a press head reads it (metadata.h kPressFeatures): the embedding of the
// contact's first frame, and the peak, the mean embedding of the frames at most kPeakRadius
// either side of the frame with the highest contact score so far (the first of equal scores).
// Fed, in order, every frame of one contact the encoder ran on; restarted at each onset. At the
// contact's last frame the peak is the whole press's: a window cut by the end keeps what is left
// of it. Made once (allocates); restart() and add() allocate nothing.
//
//   PressTracker press(dim);
//   press.add(embedding, score_dn);                 // each frame in contact
//   if (press.ready()) heads.evaluate_press(press.peak(), press.first());

#include <cstdint>
#include <span>
#include <vector>

namespace tlvlink::pipeline {

class PressTracker {
 public:
  static constexpr int32_t kPeakRadius = 2;
  // A press head answers from a contact's fourth frame on: fewer frames are a touch too brief
  // to show how its imprint grew (the fit reads only presses seen this long).
  static constexpr int32_t kMinFrames = 4;

  explicit PressTracker(int32_t embedding_dim);

  void restart();  // a new contact: forget the last one
  void add(std::span<const float> embedding, float contact_score_dn);

  int32_t frames() const { return frames_; }
  bool ready() const { return frames_ >= kMinFrames; }
  std::span<const float> first() const { return first_; }
  std::span<const float> peak() const { return peak_; }

 private:
  size_t dim_;
  int32_t frames_ = 0;
  float best_score_ = 0;
  int32_t after_best_ = 0;      // frames added to the window after the best one
  int32_t window_frames_ = 0;   // frames summed in window_
  std::vector<float> first_;    // [dim]
  std::vector<float> recent_;   // [kPeakRadius, dim]: the frames before the newest, a ring
  std::vector<double> window_;  // [dim]: sum over the peak's window
  std::vector<float> peak_;     // [dim]: window_ / window_frames_
};

}  // namespace tlvlink::pipeline
