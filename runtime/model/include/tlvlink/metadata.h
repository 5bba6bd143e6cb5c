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
// "bilinear", "area", "nearest".
constexpr const char* resize_filter_name(ResizeFilter f) {
  return f == ResizeFilter::kArea ? "area" : f == ResizeFilter::kNearest ? "nearest" : "bilinear";
}

struct InputSpec {
  int32_t height = 0, width = 0, channels = 3;
  ChannelOrder channel_order = ChannelOrder::kRGB;
  int32_t crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;  // crop_w == 0: no crop
  ResizeFilter resize_filter = ResizeFilter::kBilinear;
  std::span<const float> mean;  // per channel, applied to pixel / 255
  std::span<const float> std;
  bool background_subtraction = false;
};

// How far a head can be trusted: its accuracy on a labelled test set beside the accuracy of
// always answering that set's commonest class. head_trust.h turns it into a decision.
// The loader guarantees: accuracy and majority finite in [0, 1], n >= 1 when present.
struct HeadTrust {
  bool present = false;  // false: the file records no measurement for this head
  float accuracy = 0;
  float majority = 0;
  int64_t n = 0;
  std::string_view test_set;
  // Cross-validated records (`heads fit --images`); -1 / 0 / empty when the file has none.
  float balanced_accuracy = -1;
  float ci_low = -1, ci_high = -1;  // 95 % interval of `accuracy`
  int64_t groups = 0;
  float baseline_accuracy = -1;  // a baseline on the same folds: the head must beat it
  std::string_view baseline;
};

// What a press head reads (Metadata::press_heads): the press's peak embedding, then the peak
// minus the embedding of the contact's first frame (runtime/pipeline press_tracker.h).
inline constexpr std::string_view kPressFeatures = "press.peak,press.peak-first";
inline constexpr int32_t kPressFeatureBlocks = 2;  // embeddings' worth of features it reads

struct LinearHead {
  std::string_view name;
  std::vector<std::string_view> labels;
  std::span<const float> weight;  // [labels, embedding_dim] ([labels, 2 * dim]: a press head)
  std::span<const float> bias;    // [labels]
  HeadTrust trust = {};
  std::string_view features = {};  // a press head's kPressFeatures; empty for a per-frame head
};

struct ZeroShotHead {
  std::string_view name;
  std::vector<std::string_view> class_names;
  std::string_view prompt_template;
  std::span<const float> prompt_matrix;  // [classes, embedding_dim]
  float logit_scale = 100;
  HeadTrust trust = {};
};

struct GraspHead {
  bool present = false;
  std::string_view name;
  std::string_view feature_layout;
  std::span<const float> weight;
  float bias = 0;
  HeadTrust trust = {};
  // A head of Metadata::sensor_grasp_heads: the sensor models it was fitted on, and its expected
  // p(success) on the golden pairs as Metadata::golden_grasp (has_golden false: not stored).
  std::vector<std::string_view> sensors;
  bool has_golden = false;
  float golden = 0;
};

struct Provenance {
  std::string_view producer, created_utc, training, quantization;
  uint64_t content_checksum = 0;
};

struct GoldenPair {
  std::span<const std::byte> input;   // shaped like graph input 0
  std::span<const std::byte> output;  // shaped like graph output 0
  // Expected probabilities of every linear head, then every zero-shot head (in file order,
  // back to back) on `output` read as the embedding; empty in files written before them.
  std::span<const float> head_probabilities;
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
  // Expected grasp p(success) with golden output k as the grasp layout's feature k (pairs
  // reused in turn when fewer); absent (false) without a grasp head or in older files.
  bool has_golden_grasp = false;
  float golden_grasp = 0;
  // Grasp heads fitted on one sensor model's grasps (same feature layout as grasp_head, which
  // they require): fingers of a model one of them names use it, any other finger grasp_head.
  std::vector<GraspHead> sensor_grasp_heads;
  // Heads over a press (kPressFeatures), and their expected probabilities with golden output 0
  // as the peak and golden output 1 (0 with one pair) as the first frame, head after head
  // (empty: not stored).
  std::vector<LinearHead> press_heads;
  std::span<const float> golden_press;
};

}  // namespace tlvlink
