#include "protocol/message_samples.h"

#include <array>

namespace tlvlink::testing {
namespace {

using namespace tlvlink::protocol;

constexpr std::array<std::string_view, 4> kMaterial = {"rubber", "metal", "wood", "fabric"};
constexpr std::array<std::string_view, 2> kHardness = {"hard", "soft"};
constexpr std::array<std::string_view, 2> kGrasp = {"fail", "success"};
constexpr std::array<std::string_view, 5> kStages = {"dequeue", "decode", "preprocess", "encoder",
                                                     "heads"};
const std::array<HeadInfo, 3> kHeads = {
    // material: a cross-validated record (minor 1); hardness: accuracy only; grasp: none.
    HeadInfo{"material", HeadKind::kLinear, kMaterial, 0.158f, 0.12f, 0.11f, 0.2f, 0.15f, 0.09f,
             12},
    HeadInfo{"hardness", HeadKind::kZeroShot, kHardness, 0.737f, 0.51f, kNotRecorded, kNotRecorded,
             kNotRecorded, kNotRecorded, 0},
    HeadInfo{"grasp", HeadKind::kGrasp, kGrasp, kNotRecorded, kNotRecorded, kNotRecorded,
             kNotRecorded, kNotRecorded, kNotRecorded, 0}};
const std::array<SensorInfo, 2> kSensors = {
    SensorInfo{0, "left", "GelSight Mini", "2BDD-1", "mjpeg", 3280, 2464, 25.0f},
    SensorInfo{1, "right", "DIGIT", "D20001", "yuyv", 320, 240, 60.0f}};
constexpr std::array<uint32_t, 5> kStageNs = {120'000, 2'500'000, 800'000, 1'100'000, 30'000};
constexpr std::array<float, 4> kMaterialP = {0.7f, 0.1f, 0.15f, 0.05f};
constexpr std::array<float, 2> kHardnessP = {0.25f, 0.75f};
const std::array<HeadOutput, 2> kOutputs = {HeadOutput{0, kMaterialP}, HeadOutput{1, kHardnessP}};
std::array<float, 64> make_embedding() {
  std::array<float, 64> e{};
  for (size_t i = 0; i < e.size(); ++i) e[i] = static_cast<float>(i) * 0.03125f - 1.0f;
  return e;
}
const std::array<float, 64> kEmbedding = make_embedding();
const std::array<GraspFrame, 4> kGraspFrames = {
    GraspFrame{0, GraspPhase::kBefore, 100, 1'000'000'000},
    GraspFrame{1, GraspPhase::kBefore, 230, 1'000'500'000},
    GraspFrame{0, GraspPhase::kDuring, 110, 1'400'000'000},
    GraspFrame{1, GraspPhase::kDuring, 254, 1'400'200'000}};
const std::array<SensorStats, 2> kSensorStats = {SensorStats{0, 24.9f, 1200, 800, 400},
                                                 SensorStats{1, 59.8f, 3000, 2500, 500}};
const std::array<DropCount, 3> kDrops = {DropCount{DropCause::kCaptureGap, 3, 0},
                                         DropCount{DropCause::kQueueFull, 17, kNoSensor},
                                         DropCount{DropCause::kLinkDown, 250, kNoSensor}};

}  // namespace

Hello sample_hello() {
  Hello h;
  h.device = "gripper-7";
  h.board = "rpi5-a76";
  h.firmware_version = "0.1.0";
  h.boot_id = 0x0123456789ABCDEFull;
  h.model_id = "touch-tiny-int8";
  h.model_checksum = 0xFEDCBA9876543210ull;
  h.sensors = kSensors;
  h.heads = kHeads;
  h.stage_names = kStages;
  h.embedding_dim = 64;
  h.clock = "CLOCK_MONOTONIC";
  h.max_frame_size = kMaxFrameSize;
  return h;
}

FramePrediction sample_frame_prediction(bool with_embedding) {
  FramePrediction f;
  f.sensor = 1;
  f.frame_sequence = 4'000'000'001u;
  f.timing = FrameTiming{1'000'000'000'123, 1'000'004'000'000, 1'000'005'500'000};
  f.stage_ns = kStageNs;
  f.contact = true;
  f.heads = kOutputs;
  if (with_embedding) f.embedding = kEmbedding;
  return f;
}

GraspPrediction sample_grasp_prediction() {
  GraspPrediction g;
  g.grasp_id = 7;
  g.status = GraspStatus::kComputed;
  g.probability = 0.83f;
  g.frames = kGraspFrames;
  g.phase_source = PhaseSource::kDetected;
  g.closed_ns = 1'000'000'000;
  g.lifting_ns = 1'300'000'000;
  g.infer_end_ns = 1'450'000'000;
  return g;
}

GraspPrediction sample_grasp_not_computed() {
  GraspPrediction g;
  g.grasp_id = 8;
  g.status = GraspStatus::kNotComputed;
  g.probability = 0.5f;  // must not travel: only computed predictions carry one
  g.reason = GraspReason::kMissingFinger;
  g.reason_text = "sensor 1 delivered no frame in the 'during' phase";
  g.phase_source = PhaseSource::kCommand;
  g.closed_ns = 2'000'000'000;
  return g;
}

Stats sample_stats() {
  Stats s;
  s.uptime_ns = 3'600'000'000'000;
  s.sensors = kSensorStats;
  s.drops = kDrops;
  s.cpu_percent = 43.5f;
  s.cpu_cores = 2;
  s.rss_bytes = 40 << 20;
  s.link = LinkStats{true, 3, 100'000, 15'000'000, 400, 2, 5, 900, 262'144};
  return s;
}

ErrorReport sample_error() {
  return ErrorReport{400, "capture", "/dev/video0 disappeared (ENODEV); reopening", 0};
}
Ack sample_ack() { return Ack{41, CommandKind::kStart}; }
Nack sample_nack() {
  return Nack{42, CommandKind::kSetConfig, 300, "unknown key 'treads' (did you mean 'threads'?)"};
}
Pong sample_pong() { return Pong{43, 5'000'000'000, 5'000'150'000}; }

FrameImage sample_frame_image() {
  static const auto kData = [] {
    std::array<uint8_t, 4096> d{};
    for (size_t i = 0; i < d.size(); ++i) d[i] = static_cast<uint8_t>(i * 7 + 3);
    return d;
  }();
  static const auto kMask = [] {
    std::array<uint8_t, 32 * 24 / 8> m{};
    for (size_t i = 0; i < m.size(); ++i) m[i] = static_cast<uint8_t>(i % 3 == 0 ? 0xF0 : 0);
    return m;
  }();
  FrameImage f;
  f.sensor = 1;
  f.frame_sequence = 4242;
  f.capture_ns = 7'000'000'123;
  f.kind = ImageKind::kInput;
  f.width = 224;
  f.height = 168;
  f.contact = true;
  f.mask_width = 32;
  f.mask_height = 24;
  f.mask = kMask;
  f.data = kData;
  return f;
}

Command sample_command() {
  Command c;
  c.kind = CommandKind::kSetConfig;
  c.sensor = 1;
  c.grasp_id = 9;
  c.event_ns = 1'234'567;
  c.key = "heads";
  c.value = "material,grasp";
  c.clock_offset_ns = -42;
  c.clock_uncertainty_ns = 7;
  return c;
}

}  // namespace tlvlink::testing
