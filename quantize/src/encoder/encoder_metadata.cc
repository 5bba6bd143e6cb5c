// Metadata of the reference encoder: input spec, random heads, provenance marking it untrained.

#include <cmath>
#include <string>

#include "encoder/encoder_internal.h"

namespace tlvlink::quantize::encoder_internal {
namespace {

// Touch-and-Go's 20 material classes; the index is the dataset's material id (0..19).
const char* const kMaterials[] = {
    "concrete",         "plastic",        "glass",  "wood",  "metal", "brick", "tile", "leather",
    "synthetic fabric", "natural fabric", "rubber", "paper", "tree",  "grass", "soil", "rock",
    "gravel",           "sand",           "plants", "others"};
// Per-channel normalisation: pixel/255 in [0,1] -> [-2, 2].
constexpr float kMean = 0.5f;
constexpr float kStd = 0.25f;
// Grasp features: embeddings of both fingers before and during the lift (Calandra's predictor).
constexpr const char* kGraspLayout = "finger0.before,finger0.during,finger1.before,finger1.during";
constexpr int32_t kGraspEmbeddings = 4;

std::vector<float> random_rows(Rng& rng, size_t rows, size_t dim) {
  std::vector<float> w(rows * dim);
  const float std = 1.0f / std::sqrt(static_cast<float>(dim));
  for (float& v : w) v = std * rng.normal();
  return w;
}

LinearHeadSpec random_head(Rng& rng, std::string name, std::vector<std::string> labels,
                           size_t dim) {
  LinearHeadSpec h;
  h.name = std::move(name);
  h.weight = random_rows(rng, labels.size(), dim);
  h.bias.assign(labels.size(), 0.0f);
  h.labels = std::move(labels);
  return h;
}

}  // namespace

void fill_encoder_metadata(MetadataSpec& m, const ReferenceEncoderOptions& o) {
  const auto dim = static_cast<size_t>(o.embedding_dim);
  m.name = "tlvlink-reference-encoder-r" + std::to_string(o.resolution) +
           (o.dtype == EncoderDType::kInt8 ? "-int8" : "-fp32");
  m.input.height = m.input.width = o.resolution;
  m.input.channels = 3;
  m.input.channel_order = ChannelOrder::kRGB;
  m.input.resize_filter = ResizeFilter::kBilinear;
  m.input.mean.assign(3, kMean);
  m.input.std.assign(3, kStd);
  m.embedding_dim = o.embedding_dim;
  m.embedding_output = 0;

  Rng rng(derive_seed(o.seed, 2));
  m.linear_heads.push_back(
      random_head(rng, "material",
                  std::vector<std::string>(std::begin(kMaterials), std::end(kMaterials)), dim));
  m.linear_heads.push_back(random_head(rng, "hard_soft", {"hard", "soft"}, dim));
  m.linear_heads.push_back(random_head(rng, "rough_smooth", {"smooth", "rough"}, dim));
  m.has_grasp_head = true;
  m.grasp_head.name = "grasp";
  m.grasp_head.feature_layout = kGraspLayout;
  m.grasp_head.weight = random_rows(rng, kGraspEmbeddings, dim);
  m.grasp_head.bias = 0.0f;

  m.producer = "tlvlink gen-reference";
  m.training_json = "{\"kind\":\"random-reference\",\"seed\":" + std::to_string(o.seed) +
                    ",\"trained\":false,\"purpose\":\"testing and benchmarking only; "
                    "weights and heads are random\"}";
  m.quantization_json = "{\"kind\":\"none\"}";
}

}  // namespace tlvlink::quantize::encoder_internal
