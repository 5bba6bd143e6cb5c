#pragma once
// The stream's messages as C++ values (schema: runtime/protocol/schema/stream.fbs). The board
// fills them in to send (encode.h); the flat ones are also what decoding returns (views.h
// decodes the nested ones in place). Strings and arrays are views: they borrow the caller's
// data when encoding and the frame's bytes when decoding.

#include <cstdint>
#include <limits>
#include <span>
#include <string_view>

#include "tlvlink/protocol/wire.h"

namespace tlvlink::protocol {

inline constexpr uint8_t kNoSensor = 255;  // "all sensors" in commands, "none" in reports
inline constexpr float kNotRecorded = std::numeric_limits<float>::quiet_NaN();

// Enums mirror the schema's numbers; a decoded value may be one this build does not name
// (a newer peer): names.h prints it as a number.
enum class HeadKind : uint8_t { kLinear = 0, kZeroShot = 1, kGrasp = 2 };
enum class GraspStatus : uint8_t { kComputed = 0, kNotComputed = 1 };
enum class GraspReason : uint8_t {
  kNone = 0,
  kMissingFinger = 1,
  kLateFinger = 2,
  kNoContact = 3,
  kNoGraspHead = 4,
  kPhaseTimeout = 5,
  kAborted = 6,
  kOther = 7
};
enum class GraspPhase : uint8_t { kBefore = 0, kDuring = 1 };
enum class PhaseSource : uint8_t { kCommand = 0, kDetected = 1 };
enum class DropCause : uint8_t {
  kCaptureGap = 0,
  kCaptureError = 1,
  kInferenceBusy = 2,
  kQueueFull = 3,
  kLinkDown = 4,
  kStale = 5,
  kImageBusy = 6
};
enum class CommandKind : uint8_t {
  kNone = 0,
  kStart = 1,
  kStop = 2,
  kGraspClosed = 3,
  kGraspLifting = 4,
  kRezero = 5,
  kSetConfig = 6,
  kInfo = 7,
  kPing = 8,
  kTimeSync = 9
};

struct SensorInfo {
  uint8_t index = 0;
  std::string_view name, model, serial, pixel_format;
  uint16_t width = 0, height = 0;
  float fps = 0;
};

struct HeadInfo {
  std::string_view name;
  HeadKind kind = HeadKind::kLinear;
  std::span<const std::string_view> labels;
  float accuracy = kNotRecorded;  // from the model file, when it records it
  float majority_rate = kNotRecorded;
  // Cross-validated records (minor 1): NaN / 0 when the model records none.
  float accuracy_ci_low = kNotRecorded, accuracy_ci_high = kNotRecorded;
  float balanced_accuracy = kNotRecorded, baseline_accuracy = kNotRecorded;
  uint32_t groups = 0;
};

// Sent at every (re)connect and in answer to Info. The encoder adds schema_hash().
struct Hello {
  std::string_view device, board, firmware_version;
  uint64_t boot_id = 0;
  std::string_view model_id;
  uint64_t model_checksum = 0;
  std::span<const SensorInfo> sensors;
  std::span<const HeadInfo> heads;
  std::span<const std::string_view> stage_names;
  uint16_t embedding_dim = 0;
  std::string_view clock = "CLOCK_MONOTONIC";
  uint32_t max_frame_size = kMaxFrameSize;
};

struct FrameTiming {
  int64_t capture_ns = 0, infer_start_ns = 0, infer_end_ns = 0;
};

// Minor 3: the contact gate's state on a frame; kUnknown from an older board (absent).
enum class GateState : uint8_t { kUnknown = 0, kCalibrating = 1, kNone = 2, kContact = 3 };

struct HeadOutput {
  uint16_t head = 0;  // index into Hello::heads
  std::span<const float> probabilities;
};

// The send time is the frame header's send_ns (stamped when the frame is written).
struct FramePrediction {
  uint8_t sensor = 0;
  uint32_t frame_sequence = 0;
  FrameTiming timing;
  std::span<const uint32_t> stage_ns;
  bool contact = false;
  std::span<const HeadOutput> heads;
  std::span<const float> embedding;      // empty: not sent
  GateState gate = GateState::kUnknown;  // minor 3
  float gate_score_dn = kNotRecorded;    // minor 3: the gate's score, DN
};

struct GraspFrame {
  uint8_t sensor = 0;
  GraspPhase phase = GraspPhase::kBefore;
  uint32_t frame_sequence = 0;
  int64_t capture_ns = 0;
};

struct GraspPrediction {
  uint32_t grasp_id = 0;
  GraspStatus status = GraspStatus::kNotComputed;
  float probability = kNotRecorded;  // only with kComputed
  GraspReason reason = GraspReason::kNone;
  std::string_view reason_text;
  std::span<const GraspFrame> frames;
  PhaseSource phase_source = PhaseSource::kCommand;
  int64_t closed_ns = 0, lifting_ns = 0, infer_end_ns = 0;
};

struct DropCount {
  DropCause cause = DropCause::kQueueFull;
  uint64_t count = 0;
  uint8_t sensor = kNoSensor;
};

struct SensorStats {
  uint8_t sensor = 0;
  float fps = 0;
  uint64_t frames = 0, inferred = 0, gated = 0;
};

struct LinkStats {
  bool link_up = false;
  uint32_t reconnects = 0;
  uint64_t frames_sent = 0, bytes_sent = 0, frames_received = 0, frames_rejected = 0;
  uint32_t queue_messages = 0, queue_bytes = 0, queue_capacity_bytes = 0;
};

struct Stats {
  int64_t uptime_ns = 0;
  std::span<const SensorStats> sensors;
  std::span<const DropCount> drops;
  float cpu_percent = kNotRecorded;
  uint8_t cpu_cores = 0;
  uint64_t rss_bytes = 0;
  LinkStats link;
};

struct ErrorReport {
  uint16_t code = 0;  // tlvlink::ErrorCode
  std::string_view name, text;
  uint8_t sensor = kNoSensor;
};

struct Ack {
  uint32_t command_sequence = 0;
  CommandKind kind = CommandKind::kNone;
};

struct Nack {
  uint32_t command_sequence = 0;
  CommandKind kind = CommandKind::kNone;
  uint16_t code = 0;  // tlvlink::ErrorCode
  std::string_view text;
};

enum class ImageKind : uint8_t { kView = 0, kInput = 1 };
enum class ImageFormat : uint8_t { kJpeg = 0 };

// Minor 2: a small encoded picture of one frame and the contact gate's per-cell mask.
inline constexpr size_t kMaxMaskCells = 256 * 256;  // the contact gate's largest grid
struct FrameImage {
  uint8_t sensor = 0;
  uint32_t frame_sequence = 0;
  int64_t capture_ns = 0;
  ImageKind kind = ImageKind::kView;
  uint16_t width = 0, height = 0;
  ImageFormat format = ImageFormat::kJpeg;
  bool contact = false;
  uint8_t mask_width = 0, mask_height = 0;  // cells; 0 = no mask
  std::span<const uint8_t> mask;            // (mask_width * mask_height + 7) / 8 bytes, LSB first
  std::span<const uint8_t> data;            // the JPEG file
};
// Cell (x, y) of a mask of `width` cells across.
inline bool mask_cell(std::span<const uint8_t> mask, int width, int x, int y) {
  const size_t i = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
  return i / 8 < mask.size() && ((mask[i / 8] >> (i % 8)) & 1u) != 0;
}

// t1 = host_send_ns, t2 = board_receive_ns, t3 = this frame's header send_ns (clock.h).
struct Pong {
  uint32_t command_sequence = 0;
  int64_t host_send_ns = 0, board_receive_ns = 0;
};

struct Command {
  CommandKind kind = CommandKind::kNone;
  uint8_t sensor = kNoSensor;
  uint32_t grasp_id = 0;
  int64_t event_ns = 0;
  std::string_view key, value;
  int64_t clock_offset_ns = 0, clock_uncertainty_ns = 0;
};

// The header message type of each message struct.
template <typename M>
struct MessageTypeOf;
template <>
struct MessageTypeOf<Hello> {
  static constexpr MessageType value = MessageType::kHello;
};
template <>
struct MessageTypeOf<FramePrediction> {
  static constexpr MessageType value = MessageType::kFramePrediction;
};
template <>
struct MessageTypeOf<GraspPrediction> {
  static constexpr MessageType value = MessageType::kGraspPrediction;
};
template <>
struct MessageTypeOf<Stats> {
  static constexpr MessageType value = MessageType::kStats;
};
template <>
struct MessageTypeOf<ErrorReport> {
  static constexpr MessageType value = MessageType::kError;
};
template <>
struct MessageTypeOf<Ack> {
  static constexpr MessageType value = MessageType::kAck;
};
template <>
struct MessageTypeOf<Nack> {
  static constexpr MessageType value = MessageType::kNack;
};
template <>
struct MessageTypeOf<Pong> {
  static constexpr MessageType value = MessageType::kPong;
};
template <>
struct MessageTypeOf<FrameImage> {
  static constexpr MessageType value = MessageType::kFrameImage;
};
template <>
struct MessageTypeOf<Command> {
  static constexpr MessageType value = MessageType::kCommand;
};

}  // namespace tlvlink::protocol
