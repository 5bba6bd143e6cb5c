#pragma once
// Separable resampling of interleaved RGB with a triangle (tent) filter whose support follows
// the scale: bilinear when enlarging, an area-like average over `scale` source pixels when
// shrinking (no aliasing of camera noise or marker dots). Source coordinates outside the image
// repeat the edge. One plan serves every frame of a size: plan() allocates, run() does not.
// Used to cut a sensor's view out of the camera frame (FrameDecoder) and, in reverse, by the
// simulator to draw the camera's whole field.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlvlink::image {

// An axis map: destination pixel i (centre i + 0.5) reads the source at the continuous
// coordinate offset + (i + 0.5) * scale (pixel edges at integers).
struct AxisMap {
  double offset = 0, scale = 1;
};

// A processed axis of `processed_len` pixels reading a camera axis of `camera_len` pixels, cut
// by `crop` (a fraction of the axis) on each side.
AxisMap view_from_camera(double crop, int32_t camera_len, int32_t processed_len);

class Resampler {
 public:
  // Sizes >= 1. Allocates the taps and a ring of horizontally resampled rows.
  void plan(int32_t src_width, int32_t src_height, int32_t dst_width, int32_t dst_height,
            AxisMap x_map, AxisMap y_map);
  // src: src_height rows of src_width RGB pixels; dst: dst_height rows of dst_width.
  void run(const uint8_t* src, uint8_t* dst);
  // The same with src rows src_stride bytes apart (>= src_width * 3).
  void run_strided(const uint8_t* src, size_t src_stride, uint8_t* dst);

 private:
  // Per destination index: taps first .. first + count - 1 (valid source indices) with weights
  // weights[i * max + t] summing to 1.
  struct Taps {
    std::vector<int32_t> first, count;
    std::vector<float> weights;
    int32_t max = 0;
  };
  static Taps make_taps(int32_t src_len, int32_t dst_len, AxisMap map);
  void horizontal(const uint8_t* src_row, float* out) const;

  int32_t src_width_ = 0, dst_width_ = 0, dst_height_ = 0;
  Taps x_, y_;
  // Horizontally resampled source rows, a ring of y_.max rows: consecutive destination rows
  // share source rows, and their windows only move forward.
  std::vector<float> ring_;
  std::vector<int32_t> ring_row_;  // source row held by each slot, -1 = none
  std::vector<float*> rows_;       // the ring rows one destination row sums
  std::vector<float> acc_;         // a block of a destination row before rounding
};

}  // namespace tlvlink::image
