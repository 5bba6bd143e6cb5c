#include "stream_fixture.h"

#include <cstring>

namespace tlvlink::testing {
namespace {

using namespace tlvlink::protocol;

constexpr std::array<std::string_view, 4> kMaterial = {"rubber", "metal", "wood", "fabric"};
constexpr std::array<std::string_view, 2> kHardness = {"hard", "soft"};
constexpr float kNone = protocol::kNotRecorded;
const std::array<HeadInfo, 2> kHeads = {HeadInfo{"material", HeadKind::kLinear, kMaterial, 0.158f,
                                                 0.12f, kNone, kNone, kNone, kNone, 0},
                                        HeadInfo{"hardness", HeadKind::kLinear, kHardness, 0.737f,
                                                 0.5f, kNone, kNone, kNone, kNone, 0}};
const std::array<SensorInfo, 2> kSensors = {
    SensorInfo{0, "left", "DIGIT", "D0001", "yuyv", 320, 240, 60},
    SensorInfo{1, "right", "DIGIT", "D0002", "yuyv", 320, 240, 60}};
constexpr std::array<std::string_view, 5> kStages = {"dequeue", "decode", "preprocess", "encoder",
                                                     "heads"};

float value(uint32_t n, uint32_t k) {
  return static_cast<float>((n * 7919u + k * 104729u) % 1000u) / 1000.0f;
}

}  // namespace

Hello fixture_hello() {
  Hello h;
  h.device = "test-board";
  h.board = "host-x86_64";
  h.firmware_version = "0.1.0-test";
  h.boot_id = 0x5EED;
  h.model_id = "fixture";
  h.model_checksum = 42;
  h.sensors = kSensors;
  h.heads = kHeads;
  h.stage_names = kStages;
  h.embedding_dim = 32;
  return h;
}

FramePrediction fixture_prediction(uint32_t n, PredictionStorage& s, bool with_embedding,
                                   int64_t capture_ns) {
  for (uint32_t k = 0; k < 4; ++k) s.material[k] = value(n, k);
  for (uint32_t k = 0; k < 2; ++k) s.hardness[k] = value(n, 10 + k);
  for (uint32_t k = 0; k < 5; ++k) s.stages[k] = n * 10 + k;
  for (uint32_t k = 0; k < 32; ++k) s.embedding[k] = value(n, 100 + k) - 0.5f;
  s.heads = {HeadOutput{0, s.material}, HeadOutput{1, s.hardness}};
  FramePrediction f;
  f.sensor = static_cast<uint8_t>(n % 2);
  f.frame_sequence = n;
  f.timing = FrameTiming{capture_ns != 0 ? capture_ns : int64_t{n} * 1000, int64_t{n} * 1000 + 1,
                         int64_t{n} * 1000 + 2};
  f.stage_ns = s.stages;
  f.contact = (n % 3) == 0;
  f.heads = s.heads;
  if (with_embedding) f.embedding = s.embedding;
  return f;
}

bool fixture_prediction_intact(const FramePredictionView& v) {
  const uint32_t n = v.frame_sequence();
  PredictionStorage s;
  const FramePrediction want = fixture_prediction(n, s, !v.embedding().empty());
  if (v.sensor() != want.sensor || v.contact() != want.contact) return false;
  if (v.timing().infer_start_ns != want.timing.infer_start_ns ||
      v.timing().infer_end_ns != want.timing.infer_end_ns)
    return false;
  if (v.stage_ns().size() != 5 || std::memcmp(v.stage_ns().data(), s.stages.data(), 20) != 0)
    return false;
  if (v.head_count() != 2) return false;
  for (size_t i = 0; i < 2; ++i) {
    const HeadOutput h = v.head(i);
    if (h.head != want.heads[i].head ||
        h.probabilities.size() != want.heads[i].probabilities.size())
      return false;
    if (std::memcmp(h.probabilities.data(), want.heads[i].probabilities.data(),
                    h.probabilities.size_bytes()) != 0)
      return false;
  }
  if (!v.embedding().empty() && (v.embedding().size() != 32 ||
                                 std::memcmp(v.embedding().data(), s.embedding.data(), 128) != 0)) {
    return false;
  }
  return true;
}

}  // namespace tlvlink::testing
