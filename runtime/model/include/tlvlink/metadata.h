#pragma once
// Model metadata: how frames are preprocessed and which heads turn the embedding into
// predictions. Views into the Model's bytes (valid for the Model's lifetime).

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace tlvlink {

enum class ChannelOrder : uint8_t { kRGB = 0, kBGR = 1, kGray = 2 };
enum class ResizeFilter : uint8_t { kBilinear = 0, kArea = 1, kNearest = 2 };

struct InputSpec {
  int32_t height = 0, width = 0, channels = 3;
  ChannelOrder channel_order = ChannelOrder::kRGB;
  int32_t crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;  // crop_w == 0: no crop
  ResizeFilter resize_filter = ResizeFilter::kBilinear;
  std::span<const float> mean;  // per channel, applied to pixel / 255
  std::span<const float> std;
  bool background_subtraction = false;
};

struct LinearHead {
  std::string_view name;
  std::vector<std::string_view> labels;
  std::span<const float> weight;  // [labels, embedding_dim]
  std::span<const float> bias;    // [labels]
};

struct ZeroShotHead {
  std::string_view name;
  std::vector<std::string_view> class_names;
  std::string_view prompt_template;
  std::span<const float> prompt_matrix;  // [classes, embedding_dim]
  float logit_scale = 100;
};

struct GraspHead {
  bool present = false;
  std::string_view name;
  std::string_view feature_layout;
  std::span<const float> weight;
  float bias = 0;
};

struct Provenance {
  std::string_view producer, created_utc, training, quantization;
  uint64_t content_checksum = 0;
};

struct GoldenPair {
  std::span<const std::byte> input;   // shaped like graph input 0
  std::span<const std::byte> output;  // shaped like graph output 0
};

struct Metadata {
  std::string_view name;
  InputSpec input;
  int32_t embedding_dim = 0;
  int32_t embedding_output = 0;
  std::vector<LinearHead> linear_heads;
  std::vector<ZeroShotHead> zero_shot_heads;
  GraspHead grasp_head;
  Provenance provenance;
  std::vector<GoldenPair> golden;
};

}  // namespace tlvlink
