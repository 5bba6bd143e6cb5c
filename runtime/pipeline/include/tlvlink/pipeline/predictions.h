#pragma once
// What the pipeline produces, as fixed-size records (no heap: they travel through the daemon's
// bounded queues and into the output encoders). Capacity limits are errors at start-up (a model
// with more heads or labels than fit is refused, naming the head), never truncations.

#include <array>
#include <cstdint>

namespace tlvlink::pipeline {

inline constexpr int32_t kMaxSensors = 4;
inline constexpr int32_t kMaxHeads = 8;        // per-frame heads reported
inline constexpr int32_t kMaxLabels = 32;      // labels of one head
inline constexpr int32_t kMaxGraspFrames = 6;  // frames a grasp head reads (2 fingers x 3)
// Features a grasp head reads: an embedding per frame and a difference per finger.
inline constexpr int32_t kMaxGraspFeatures = kMaxGraspFrames + 2;
inline constexpr int32_t kMaxReason = 256;  // "not computed" explanations (an Error fits)
// ProcessorOptions::report_embedding: the embedding and the int8 tensor it comes from, copied
// into each encoded frame's record (a model with more is refused at start, naming the limit).
inline constexpr int32_t kMaxReportedEmbedding = 256;
inline constexpr int32_t kMaxReportedInt8 = 512;

// The stages a frame goes through; per-stage times are CLOCK_MONOTONIC nanoseconds.
struct FrameTimes {
  int64_t capture_ns = 0;       // the buffer's timestamp: when the camera finished the frame
  int64_t dequeued_ns = 0;      // the capture thread had it
  int64_t decoded_ns = 0;       // camera bytes -> the sensor's processed RGB frame
  int64_t gated_ns = 0;         // contact decision made
  int64_t preprocessed_ns = 0;  // model input written (0 when the encoder was skipped)
  int64_t inferred_ns = 0;      // encoder done (0 when skipped)
  int64_t heads_ns = 0;         // heads evaluated (0 when skipped)
  int64_t written_ns = 0;       // the output stage wrote it (set by the writer)
};

struct HeadProbabilities {
  int16_t head = 0;  // index into the model's per-frame heads (HeadEvaluator::results)
  int16_t labels = 0;
  int16_t top = 0;                              // argmax of the smoothed probabilities
  std::array<float, kMaxLabels> probability{};  // smoothed (see FrameProcessor) probabilities
};

struct FramePrediction {
  int32_t sensor = 0;     // index in the daemon's sensor list (= finger for grasp heads)
  uint64_t sequence = 0;  // the source's normalised frame sequence
  FrameTimes times;
  uint8_t contact_state = 0;  // ContactState
  bool encoder_ran = false;   // false: gated (no contact), no head results in this record
  float contact_score_dn = 0;
  int32_t head_count = 0;
  std::array<HeadProbabilities, kMaxHeads> heads{};
  // Only with ProcessorOptions::report_embedding and when the encoder ran (0 otherwise): the
  // encoder's embedding (float) and the int8 tensor where the model's int8 part ends (the input
  // of its last Dequantize, or the output itself for an all-int8 model; 0 values if it has none).
  int32_t embedding_dim = 0;
  std::array<float, kMaxReportedEmbedding> embedding{};
  int32_t int8_count = 0;
  std::array<int8_t, kMaxReportedInt8> int8_values{};
};

struct GraspFrameRef {
  int32_t finger = 0;
  uint8_t moment = 0;  // heads::Moment
  uint64_t sequence = 0;
  int64_t capture_ns = 0;
};

struct GraspPrediction {
  uint64_t grasp_id = 0;
  bool computed = false;
  float probability = 0;      // p(success) when computed
  int64_t started_ns = 0;     // contact onset (detected) or the "closed" mark (commanded)
  int64_t decided_ns = 0;     // when the prediction (or the failure) was made
  int32_t frame_count = 0;    // the frames the head read, each once, in layout order
  int32_t feature_count = 0;  // the features it read (its layout's entries)
  std::array<GraspFrameRef, kMaxGraspFrames> frames{};
  std::array<char, kMaxReason> reason{};  // why not computed ("" when computed)
};

}  // namespace tlvlink::pipeline
