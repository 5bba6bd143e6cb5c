// Loaded metadata (views) -> owned MetadataSpec, for rewriting a model.

#include "tlvlink/quantize/model_copy.h"

namespace tlvlink::quantize {
namespace {
std::vector<std::string> strings(const std::vector<std::string_view>& v) {
  return {v.begin(), v.end()};
}
std::vector<float> floats(std::span<const float> v) { return {v.begin(), v.end()}; }
HeadTrustSpec trust(const HeadTrust& t) {
  HeadTrustSpec s;
  s.present = t.present;
  s.accuracy = t.accuracy;
  s.majority = t.majority;
  s.n = t.n;
  s.test_set = t.test_set;
  s.balanced_accuracy = t.balanced_accuracy;
  s.ci_low = t.ci_low;
  s.ci_high = t.ci_high;
  s.groups = t.groups;
  s.baseline_accuracy = t.baseline_accuracy;
  s.baseline = t.baseline;
  return s;
}
GraspHeadSpec grasp_head(const GraspHead& h) {
  return {std::string(h.name), std::string(h.feature_layout),
          floats(h.weight),    h.bias,
          trust(h.trust),      strings(h.sensors)};
}
LinearHeadSpec linear_head(const LinearHead& h) {
  return {std::string(h.name), strings(h.labels), floats(h.weight),
          floats(h.bias),      trust(h.trust),    std::string(h.features)};
}
}  // namespace

MetadataSpec metadata_spec_from(const Metadata& m) {
  MetadataSpec s;
  s.name = m.name;
  const InputSpec& in = m.input;
  s.input = {in.height,        in.width,        in.channels,    in.channel_order,
             in.crop_x,        in.crop_y,       in.crop_w,      in.crop_h,
             in.resize_filter, floats(in.mean), floats(in.std), in.background_subtraction};
  s.embedding_dim = m.embedding_dim;
  s.embedding_output = m.embedding_output;
  for (const LinearHead& h : m.linear_heads) s.linear_heads.push_back(linear_head(h));
  for (const ZeroShotHead& h : m.zero_shot_heads) {
    s.zero_shot_heads.push_back({std::string(h.name), strings(h.class_names),
                                 std::string(h.prompt_template), floats(h.prompt_matrix),
                                 h.logit_scale, trust(h.trust)});
  }
  s.has_grasp_head = m.grasp_head.present;
  if (s.has_grasp_head) s.grasp_head = grasp_head(m.grasp_head);
  for (const GraspHead& h : m.sensor_grasp_heads) s.sensor_grasp_heads.push_back(grasp_head(h));
  for (const LinearHead& h : m.press_heads) s.press_heads.push_back(linear_head(h));
  s.producer = m.provenance.producer;
  s.created_utc = m.provenance.created_utc;
  s.training_json = m.provenance.training;
  s.quantization_json = m.provenance.quantization;
  return s;
}

}  // namespace tlvlink::quantize
