#pragma once
// Payload -> message. Each decode_* function verifies the payload first (flatbuffers Verifier
// with bounded depth and table count: payloads are untrusted input) and then reads it in place:
// no copy, no allocation. Views and the string_views/spans they return point into the payload
// and stay valid as long as its bytes do. Fields a newer peer added are skipped; fields an older
// peer did not send read as their defaults.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/protocol/messages.h"

namespace tlvlink::protocol {

class HeadInfoView {
 public:
  std::string_view name() const;
  HeadKind kind() const;
  size_t label_count() const;
  std::string_view label(size_t i) const;
  float accuracy() const;       // NaN when not recorded
  float majority_rate() const;  // NaN when not recorded
  // Minor 1 (NaN / 0 when not recorded, and from a board of minor 0).
  float accuracy_ci_low() const;
  float accuracy_ci_high() const;
  float balanced_accuracy() const;
  float baseline_accuracy() const;
  uint32_t groups() const;

 private:
  friend class HelloView;
  explicit HeadInfoView(const void* table) : table_(table) {}
  const void* table_;
};

class HelloView {
 public:
  std::string_view device() const;
  std::string_view board() const;
  std::string_view firmware_version() const;
  uint64_t boot_id() const;
  uint64_t schema_hash() const;
  std::string_view model_id() const;
  uint64_t model_checksum() const;
  size_t sensor_count() const;
  SensorInfo sensor(size_t i) const;
  size_t head_count() const;
  HeadInfoView head(size_t i) const;
  size_t stage_name_count() const;
  std::string_view stage_name(size_t i) const;
  uint16_t embedding_dim() const;
  std::string_view clock() const;
  uint32_t max_frame_size() const;

 private:
  friend Result<HelloView> decode_hello(std::span<const std::byte>);
  explicit HelloView(const void* table) : table_(table) {}
  const void* table_;
};

class FramePredictionView {
 public:
  uint8_t sensor() const;
  uint32_t frame_sequence() const;
  FrameTiming timing() const;
  std::span<const uint32_t> stage_ns() const;
  bool contact() const;
  size_t head_count() const;
  HeadOutput head(size_t i) const;
  std::span<const float> embedding() const;  // empty when not sent
  GateState gate() const;                    // minor 3; kUnknown from an older board
  float gate_score_dn() const;               // minor 3; NaN from an older board

 private:
  friend Result<FramePredictionView> decode_frame_prediction(std::span<const std::byte>);
  explicit FramePredictionView(const void* table) : table_(table) {}
  const void* table_;
};

class GraspPredictionView {
 public:
  uint32_t grasp_id() const;
  GraspStatus status() const;
  float probability() const;  // NaN unless computed
  GraspReason reason() const;
  std::string_view reason_text() const;
  size_t frame_count() const;
  GraspFrame frame(size_t i) const;
  PhaseSource phase_source() const;
  int64_t closed_ns() const;
  int64_t lifting_ns() const;
  int64_t infer_end_ns() const;

 private:
  friend Result<GraspPredictionView> decode_grasp_prediction(std::span<const std::byte>);
  explicit GraspPredictionView(const void* table) : table_(table) {}
  const void* table_;
};

class StatsView {
 public:
  int64_t uptime_ns() const;
  size_t sensor_count() const;
  SensorStats sensor(size_t i) const;
  size_t drop_count() const;
  DropCount drop(size_t i) const;
  float cpu_percent() const;  // NaN when not measured
  uint8_t cpu_cores() const;
  uint64_t rss_bytes() const;
  LinkStats link() const;

 private:
  friend Result<StatsView> decode_stats(std::span<const std::byte>);
  explicit StatsView(const void* table) : table_(table) {}
  const void* table_;
};

// kProtocolMalformed when the payload is not a valid table of the message's type.
Result<HelloView> decode_hello(std::span<const std::byte> payload);
Result<FramePredictionView> decode_frame_prediction(std::span<const std::byte> payload);
Result<GraspPredictionView> decode_grasp_prediction(std::span<const std::byte> payload);
Result<StatsView> decode_stats(std::span<const std::byte> payload);
Result<FrameImage> decode_frame_image(std::span<const std::byte> payload);  // views into it
Result<ErrorReport> decode_error_report(std::span<const std::byte> payload);
Result<Ack> decode_ack(std::span<const std::byte> payload);
Result<Nack> decode_nack(std::span<const std::byte> payload);
Result<Pong> decode_pong(std::span<const std::byte> payload);
Result<Command> decode_command(std::span<const std::byte> payload);

// Verifies a payload of any known type (kProtocolUnsupported for an unknown type, which a
// reader skips): the fuzz target and the receivers' one entry point.
Status verify_payload(MessageType type, std::span<const std::byte> payload);

}  // namespace tlvlink::protocol
