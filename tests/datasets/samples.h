#pragma once
// Hand-made samples, episodes and temp dirs for the dataset tests (no generator needed).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "tlvlink/datasets/records.h"

namespace tlvlink::testing {

// A smooth, seed-dependent RGB image (JPEG-friendly, so round trips stay close).
datasets::RgbImage smooth_image(int32_t height, int32_t width, uint64_t seed);

// Session "20220101_0000SS" (SS = session), one object per session, material class
// session % 20, rough -1/0/1 by frame, descriptions that differ per frame.
datasets::TouchSample touch_sample(int32_t session, int32_t frame);
std::vector<datasets::TouchSample> touch_set(int32_t sessions, int32_t frames);

// Object "object_NN", grasp k: gripping when k is even.
datasets::GraspEpisode grasp_episode(int32_t object, int32_t grasp);

// Mean and max absolute difference of two same-size images (max = 255 on a size mismatch).
struct ImageDiff {
  double mean = 0;
  int32_t max = 0;
};
ImageDiff image_diff(const datasets::RgbImage& a, const datasets::RgbImage& b);

std::vector<std::string> read_lines(const std::string& path);
void write_lines(const std::string& path, const std::vector<std::string>& lines);

}  // namespace tlvlink::testing
