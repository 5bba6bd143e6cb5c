#pragma once
// Writes .tlvm model files (host side). The builder does not validate: it can write any graph,
// including deliberately broken ones for tests. Validation is the loader's job
// (tlvlink::Model::load), so a file is only trusted once it has been loaded.
//
//   ModelBuilder b;
//   int32_t x = b.add_activation("input", DType::kFloat32, {1, 96, 96, 3});
//   int32_t w = b.add_constant<float>("stem.w", {16, 3, 3, 3}, weights);
//   int32_t y = b.add_activation("stem.out", DType::kFloat32, {1, 48, 48, 16});
//   b.add_op(OpType::kConv2D, "stem", {x, w, kNoTensor}, y, Conv2DParams{...});
//   b.set_inputs({x}); b.set_outputs({y});
//   std::vector<std::byte> file = b.finish();

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/graph.h"
#include "tlvlink/metadata.h"

namespace tlvlink::verify {
struct GoldenHeadOutputs;
}

namespace tlvlink::quantize {

struct QuantSpec {
  std::vector<float> scale;  // empty: not quantized
  std::vector<int32_t> zero_point;
  int32_t axis = -1;

  static QuantSpec per_tensor(float scale, int32_t zero_point) {
    return {{scale}, {zero_point}, -1};
  }
  static QuantSpec per_channel(std::vector<float> scales, int32_t axis);  // zero points all 0
};

// Owning counterparts of metadata.h, for writing.
struct HeadTrustSpec {
  bool present = false;  // false: no trust record is written
  float accuracy = 0, majority = 0;
  int64_t n = 0;
  std::string test_set;
  float balanced_accuracy = -1, ci_low = -1, ci_high = -1;  // metadata.h HeadTrust
  int64_t groups = 0;
  float baseline_accuracy = -1;
  std::string baseline;
};
struct LinearHeadSpec {
  std::string name;
  std::vector<std::string> labels;
  std::vector<float> weight, bias;
  HeadTrustSpec trust = {};
  std::string features = {};  // a press head's kPressFeatures (metadata.h); empty: per-frame
};
struct ZeroShotHeadSpec {
  std::string name;
  std::vector<std::string> class_names;
  std::string prompt_template;
  std::vector<float> prompt_matrix;
  float logit_scale = 100;
  HeadTrustSpec trust = {};
};
struct GraspHeadSpec {
  std::string name, feature_layout;
  std::vector<float> weight;
  float bias = 0;
  HeadTrustSpec trust = {};
  std::vector<std::string> sensors = {};  // a sensor grasp head's sensor models (metadata.h)
};
struct InputSpecDef {
  int32_t height = 0, width = 0, channels = 3;
  ChannelOrder channel_order = ChannelOrder::kRGB;
  int32_t crop_x = 0, crop_y = 0, crop_w = 0, crop_h = 0;
  ResizeFilter resize_filter = ResizeFilter::kBilinear;
  std::vector<float> mean, std;
  bool background_subtraction = false;
};
struct MetadataSpec {
  std::string name;
  InputSpecDef input;
  int32_t embedding_dim = 0;
  int32_t embedding_output = 0;
  std::vector<LinearHeadSpec> linear_heads;
  std::vector<ZeroShotHeadSpec> zero_shot_heads;
  bool has_grasp_head = false;
  GraspHeadSpec grasp_head;
  // Heads fitted on one sensor model's grasps (metadata.h Metadata::sensor_grasp_heads).
  std::vector<GraspHeadSpec> sensor_grasp_heads;
  // Heads over a press (metadata.h Metadata::press_heads; features = kPressFeatures).
  std::vector<LinearHeadSpec> press_heads;
  std::string producer = "tlvlink";
  std::string created_utc;  // empty: filled with the current time at finish()
  std::string training_json, quantization_json;
  // Golden I/O pairs: raw bytes shaped like graph input 0 / output 0.
  std::vector<std::pair<std::vector<std::byte>, std::vector<std::byte>>> golden;
};

class ModelBuilder {
 public:
  int32_t add_activation(std::string name, DType dtype, std::vector<int32_t> shape,
                         QuantSpec quant = {});
  int32_t add_constant_bytes(std::string name, DType dtype, std::vector<int32_t> shape,
                             std::span<const std::byte> data, QuantSpec quant = {});
  template <typename T>
  int32_t add_constant(std::string name, std::vector<int32_t> shape, std::span<const T> data,
                       QuantSpec quant = {});

  // inputs: up to 3 tensor indices (kNoTensor for an absent optional input such as bias).
  void add_op(OpType type, std::string name, std::vector<int32_t> inputs, int32_t output,
              OpParams params = NoParams{});

  void set_inputs(std::vector<int32_t> inputs) { inputs_ = std::move(inputs); }
  void set_outputs(std::vector<int32_t> outputs) { outputs_ = std::move(outputs); }
  MetadataSpec& metadata() { return metadata_; }

  // Test hooks for crafting bad files.
  void set_schema_version(uint32_t v) { schema_version_ = v; }
  void set_checksum_override(uint64_t c) {
    checksum_override_ = c;
    has_checksum_override_ = true;
  }

  size_t tensor_count() const { return tensors_.size(); }

  // Serialises the model: the flatbuffer (with the legacy content checksum unless overridden,
  // and the golden pairs' head outputs when the loader accepts it) followed by its integrity
  // trailer (tlvlink/model_integrity.h, unsigned).
  std::vector<std::byte> finish() const;

 private:
  std::vector<std::byte> serialize(const verify::GoldenHeadOutputs* heads) const;
  struct TensorDef {
    std::string name;
    DType dtype;
    std::vector<int32_t> shape;
    QuantSpec quant;
    uint32_t buffer = 0;
  };
  struct OpDef {
    OpType type;
    std::string name;
    std::vector<int32_t> inputs;
    int32_t output;
    OpParams params;
  };
  std::vector<TensorDef> tensors_;
  std::vector<OpDef> ops_;
  std::vector<std::vector<std::byte>> buffers_{{}};  // buffer 0: empty
  std::vector<int32_t> inputs_, outputs_;
  MetadataSpec metadata_;
  uint32_t schema_version_ = 1;
  uint64_t checksum_override_ = 0;
  bool has_checksum_override_ = false;
};

template <typename T>
int32_t ModelBuilder::add_constant(std::string name, std::vector<int32_t> shape,
                                   std::span<const T> data, QuantSpec quant) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, int8_t> ||
                std::is_same_v<T, int32_t> || std::is_same_v<T, uint8_t>);
  constexpr DType dtype = std::is_same_v<T, float>     ? DType::kFloat32
                          : std::is_same_v<T, int8_t>  ? DType::kInt8
                          : std::is_same_v<T, int32_t> ? DType::kInt32
                                                       : DType::kUInt8;
  return add_constant_bytes(std::move(name), dtype, std::move(shape), std::as_bytes(data),
                            std::move(quant));
}

}  // namespace tlvlink::quantize
