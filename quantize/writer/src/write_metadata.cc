#include <chrono>
#include <ctime>

#include "writer_internal.h"

namespace tlvlink::quantize::writer_internal {
namespace {

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

flatbuffers::Offset<fb::HeadTrust> write_trust(flatbuffers::FlatBufferBuilder& fbb,
                                               const HeadTrustSpec& t) {
  if (!t.present) return 0;
  const auto test_set = fbb.CreateString(t.test_set);
  const auto baseline = t.baseline.empty() ? 0 : fbb.CreateString(t.baseline);
  return fb::CreateHeadTrust(fbb, t.accuracy, t.majority, t.n, test_set, t.balanced_accuracy,
                             t.ci_low, t.ci_high, t.groups, t.baseline_accuracy, baseline);
}

// golden: the head's p(success) on the golden pairs (a sensor grasp head's), or null.
flatbuffers::Offset<fb::GraspHead> write_grasp_head(flatbuffers::FlatBufferBuilder& fbb,
                                                    const GraspHeadSpec& g, const float* golden) {
  // Last field first, as the one call with every argument built in place did under GCC: files
  // without the appended fields stay byte for byte what they were.
  const auto golden_value = golden == nullptr ? 0 : fbb.CreateVector(golden, 1);
  const auto sensors = g.sensors.empty() ? 0 : fbb.CreateVectorOfStrings(g.sensors);
  const auto trust = write_trust(fbb, g.trust);
  const auto weight = fbb.CreateVector(g.weight);
  const auto layout = fbb.CreateString(g.feature_layout);
  const auto name = fbb.CreateString(g.name);
  return fb::CreateGraspHead(fbb, name, layout, weight, g.bias, trust, sensors, golden_value);
}

flatbuffers::Offset<fb::LinearHead> write_linear_head(flatbuffers::FlatBufferBuilder& fbb,
                                                      const LinearHeadSpec& h) {
  // Last field first (as GCC evaluated the one call's arguments): a per-frame head, which has no
  // features, keeps the bytes it had before the field existed.
  const auto features = h.features.empty() ? 0 : fbb.CreateString(h.features);
  const auto trust = write_trust(fbb, h.trust);
  const auto bias = fbb.CreateVector(h.bias);
  const auto weight = fbb.CreateVector(h.weight);
  const auto labels = fbb.CreateVectorOfStrings(h.labels);
  const auto name = fbb.CreateString(h.name);
  return fb::CreateLinearHead(fbb, name, labels, weight, bias, trust, features);
}

}  // namespace

flatbuffers::Offset<fb::Metadata> write_metadata(flatbuffers::FlatBufferBuilder& fbb,
                                                 const MetadataSpec& spec,
                                                 std::span<const GoldenIndices> golden_buffers,
                                                 const verify::GoldenHeadOutputs* heads,
                                                 uint64_t checksum) {
  flatbuffers::Offset<fb::InputSpec> input = 0;
  if (spec.input.height > 0) {
    const InputSpecDef& in = spec.input;
    input = fb::CreateInputSpec(
        fbb, in.height, in.width, in.channels, static_cast<fb::ChannelOrder>(in.channel_order),
        in.crop_x, in.crop_y, in.crop_w, in.crop_h, static_cast<fb::ResizeFilter>(in.resize_filter),
        fbb.CreateVector(in.mean), fbb.CreateVector(in.std), in.background_subtraction);
  }
  std::vector<flatbuffers::Offset<fb::LinearHead>> linear;
  for (const auto& h : spec.linear_heads) linear.push_back(write_linear_head(fbb, h));
  std::vector<flatbuffers::Offset<fb::ZeroShotHead>> zero_shot;
  for (const auto& h : spec.zero_shot_heads) {
    zero_shot.push_back(fb::CreateZeroShotHead(
        fbb, fbb.CreateString(h.name), fbb.CreateVectorOfStrings(h.class_names),
        fbb.CreateString(h.prompt_template), fbb.CreateVector(h.prompt_matrix), h.logit_scale,
        write_trust(fbb, h.trust)));
  }
  flatbuffers::Offset<fb::GraspHead> grasp = 0;
  if (spec.has_grasp_head) grasp = write_grasp_head(fbb, spec.grasp_head, nullptr);
  std::vector<flatbuffers::Offset<fb::GraspHead>> sensor_grasp;
  for (size_t i = 0; i < spec.sensor_grasp_heads.size(); ++i) {
    const float* golden =
        heads != nullptr && i < heads->sensor_grasp.size() ? &heads->sensor_grasp[i] : nullptr;
    sensor_grasp.push_back(write_grasp_head(fbb, spec.sensor_grasp_heads[i], golden));
  }
  auto provenance = fb::CreateProvenance(
      fbb, fbb.CreateString(spec.producer),
      fbb.CreateString(spec.created_utc.empty() ? utc_now() : spec.created_utc),
      fbb.CreateString(spec.training_json), fbb.CreateString(spec.quantization_json), checksum);
  std::vector<flatbuffers::Offset<fb::GoldenPair>> golden;
  for (size_t i = 0; i < golden_buffers.size(); ++i) {
    flatbuffers::Offset<flatbuffers::Vector<float>> probabilities = 0;
    if (heads != nullptr && i < heads->pairs.size())
      probabilities = fbb.CreateVector(heads->pairs[i]);
    golden.push_back(fb::CreateGoldenPair(fbb, golden_buffers[i].input, golden_buffers[i].output,
                                          probabilities));
  }
  flatbuffers::Offset<flatbuffers::Vector<float>> golden_grasp = 0;
  if (heads != nullptr && heads->has_grasp) golden_grasp = fbb.CreateVector(&heads->grasp, 1);
  // Appended fields before the others (see write_linear_head): absent ones add no bytes.
  flatbuffers::Offset<flatbuffers::Vector<float>> golden_press = 0;
  if (heads != nullptr && !heads->press.empty()) golden_press = fbb.CreateVector(heads->press);
  std::vector<flatbuffers::Offset<fb::LinearHead>> press;
  for (const auto& h : spec.press_heads) press.push_back(write_linear_head(fbb, h));
  const auto press_heads = press.empty() ? 0 : fbb.CreateVector(press);
  return fb::CreateMetadata(
      fbb, fbb.CreateString(spec.name), input, spec.embedding_dim, spec.embedding_output,
      fbb.CreateVector(linear), fbb.CreateVector(zero_shot), grasp, provenance,
      fbb.CreateVector(golden), golden_grasp,
      sensor_grasp.empty() ? 0 : fbb.CreateVector(sensor_grasp), press_heads, golden_press);
}

}  // namespace tlvlink::quantize::writer_internal
