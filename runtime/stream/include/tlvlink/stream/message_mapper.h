#pragma once
// Pipeline records -> stream protocol messages (runtime/protocol): FramePrediction (with the
// per-stage latencies named by kStageNames), GraspPrediction, ErrorReport, Stats and FrameImage.
// The messages returned point into this object's scratch and into the record given: use them (post,
// encode) before the next call. No allocation.

#include <array>
#include <cstdint>
#include <span>

#include "tlvlink/pipeline/predictions.h"
#include "tlvlink/protocol/messages.h"
#include "tlvlink/stream/stages.h"

namespace tlvlink::stream {

// A board's counters for one Stats message, by the protocol's drop causes.
struct StreamTotals {
  double seconds = 0;  // since start
  int32_t sensors = 0;
  std::array<double, pipeline::kMaxSensors> sensor_fps{};
  std::array<uint64_t, pipeline::kMaxSensors> sensor_frames{}, sensor_encoded{}, sensor_gated{};
  uint64_t capture_gap = 0;     // the camera's sequence jumped
  uint64_t capture_error = 0;   // bad or undecodable camera frames
  uint64_t inference_busy = 0;  // frames skipped or dropped because the pipeline was behind
  uint64_t queue_full = 0;      // records dropped on their way to the link
  bool frame_images = false;    // the board sends FrameImages: its image_busy count is reported
  uint64_t image_busy = 0;      // FrameImages not sent: the board's image slots or the link busy
  double cpu_percent = 0;
  uint8_t cpu_cores = 0;
  uint64_t rss_bytes = 0;
};

// One encoded picture of a frame (protocol FrameImage, minor 2), as a board program made it.
// The spans borrow the program's buffers.
struct FrameImageRecord {
  int32_t sensor = 0;
  uint64_t sequence = 0;
  int64_t capture_ns = 0;
  bool input = false;  // the model's input; false: the decoded camera view
  int32_t width = 0, height = 0;
  bool contact = false;
  int32_t mask_width = 0, mask_height = 0;  // the contact gate's grid (cells)
  std::span<const uint8_t> mask;            // ContactGate::contact_mask bits
  std::span<const uint8_t> jpeg;
};

class MessageMapper {
 public:
  // detected_grasps: grasps are found from contact (GraspPrediction.phase_source kDetected), not
  // marked by the controller's commands.
  explicit MessageMapper(bool detected_grasps) : detected_(detected_grasps) {}

  protocol::FramePrediction frame(const pipeline::FramePrediction& p);
  protocol::GraspPrediction grasp(const pipeline::GraspPrediction& g);
  protocol::Stats stats(const StreamTotals& t);
  // Thread-safe (no scratch): a board may encode and post images on a thread of their own.
  static protocol::FrameImage image(const FrameImageRecord& r);
  // Something that happened on the board: `error` ones carry ErrorCode::kCapture; sensor -1 is
  // the board itself. `text` must outlive the message.
  static protocol::ErrorReport event(bool error, int32_t sensor, const char* text);

 private:
  bool detected_ = false;
  std::array<protocol::HeadOutput, pipeline::kMaxHeads> head_outputs_{};
  std::array<uint32_t, kStageNames.size()> stage_ns_{};
  std::array<protocol::GraspFrame, pipeline::kMaxGraspFrames> grasp_frames_{};
  std::array<protocol::SensorStats, pipeline::kMaxSensors> sensor_stats_{};
  std::array<protocol::DropCount, 5> drops_{};
};

}  // namespace tlvlink::stream
