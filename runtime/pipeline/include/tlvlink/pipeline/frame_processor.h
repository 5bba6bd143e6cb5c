#pragma once
// The per-frame chain after decoding, for all sensors of one model: contact gate -> (if touching,
// or if the grasp logic needs the frame) preprocessing -> encoder -> heads -> smoothing, the
// press heads over each sensor's contact so far (press_tracker.h), and the grasp tracker over
// the fingers. Pure logic on one thread: the daemon calls it from its
// inference thread, tests call it with replayed frames. Made once (allocates); process()
// allocates nothing.
//
// Ownership: the processor borrows the Model and the Executor (created for that model) for its
// whole lifetime; it owns the gates, plans, heads evaluator, smoothers and tracker.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/executor.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/image/image.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/model.h"
#include "tlvlink/pipeline/contact_gate.h"
#include "tlvlink/pipeline/grasp_tracker.h"
#include "tlvlink/pipeline/predictions.h"
#include "tlvlink/pipeline/press_tracker.h"
#include "tlvlink/pipeline/smoother.h"

namespace tlvlink::pipeline {

// One sensor as the processor sees it: its processed frames' size, its finger (-1: not part of
// a grasp; 0 = A, 1 = B) and its sensor model (capture/sensor_models.h: "gelsight-mini",
// "digit"; empty: not known), which picks the grasp head fitted on that model when the model
// file has one.
struct SensorSetup {
  std::string name;
  int32_t width = 0, height = 0, channels = 3;
  int32_t finger = -1;
  std::string sensor_model;
};

struct ProcessorOptions {
  bool contact_gating = true;  // false: every frame is encoded
  ContactGateOptions contact;
  bool grasp = true;  // track grasps when the model has a grasp head and fingers A, B
  GraspOptions grasp_options;
  int64_t smoothing_tau_ns = 150'000'000;
  // The heads reported, by name; empty = every probe and press head except those the model's
  // trust record marks untrusted (head_trust.h: not better than the majority class on their own
  // test set); zero-shot and untrusted heads only when named. An unknown name is an error
  // listing the model's heads. A press head is reported, unsmoothed (it reads the whole contact
  // already), on a sensor's frames in contact from the contact's PressTracker::kMinFrames-th on.
  std::vector<std::string> heads;
  // Copy the embedding and the int8 tensor it comes from into every encoded frame's record
  // (FramePrediction::embedding / int8_values): host-vs-board comparisons. The int8 tensor is
  // an intermediate activation: the executor must be created with expose_all_tensors.
  bool report_embedding = false;
};

struct ProcessorCounters {
  uint64_t frames = 0, encoder_runs = 0, gated = 0, grasp_forced = 0;
  uint64_t grasps_computed = 0, grasps_not_computed = 0;
  std::array<uint64_t, kMaxSensors> sensor_frames{}, sensor_encoder_runs{}, sensor_gated{};
};

class FrameProcessor {
 public:
  static Result<std::unique_ptr<FrameProcessor>> create(const Model& model, Executor& executor,
                                                        std::span<const SensorSetup> sensors,
                                                        const ProcessorOptions& options);

  // One processed frame of `sensor` (times filled up to decoded_ns). Fills `out`. Errors: a frame
  // of the wrong size, a failed invoke (non-finite values), named with the sensor.
  Status process(int32_t sensor, uint64_t sequence, const image::ImageView& frame,
                 const FrameTimes& times, FramePrediction& out);

  // Finished grasps since the last call, probability filled when computed. False when none.
  bool take_grasp(GraspPrediction& out);
  void tick(int64_t now_ns);  // lets grasps waiting for a silent camera time out

  void rezero(int32_t sensor);  // -1: every sensor
  bool mark_closed(int64_t t_ns);
  bool mark_lifting(int64_t t_ns);

  // The reported heads, in FramePrediction::heads order (index into HeadEvaluator::results()).
  std::span<const int16_t> reported_heads() const { return reported_; }
  const heads::HeadEvaluator& heads() const { return heads_; }
  bool tracks_grasps() const { return tracker_ != nullptr; }
  // The grasp head used (HeadEvaluator index): the fingers' sensor model's head when both
  // fingers are of one model and the file has a head for it, else 0 (fitted on every sensor).
  size_t grasp_head() const { return grasp_head_; }
  const ProcessorCounters& counters() const { return counters_; }
  const ContactGate& gate(int32_t sensor) const {
    return sensors_[static_cast<size_t>(sensor)].gate;
  }
  // The sensor's crop and resize to the model's input (resize(): the input as uint8 pixels).
  const image::PreprocessPlan& plan(int32_t sensor) const {
    return sensors_[static_cast<size_t>(sensor)].plan;
  }

 private:
  struct Sensor {
    SensorSetup setup;
    ContactGate gate;
    image::PreprocessPlan plan;
    std::vector<ProbabilitySmoother> smoothers;  // one per reported head
    PressTracker press;                          // the contact so far, for the press heads
    // The grasp head's difference features: the model's crop and resize in DN (a finger whose
    // difference the layout reads; unset otherwise).
    std::optional<image::PreprocessPlan> difference_plan;
  };
  FrameProcessor(const Model& model, Executor& executor) : model_(model), executor_(executor) {}
  Status embed(Sensor& s, const image::ImageView& frame, FrameTimes& times);
  Status report_heads(Sensor& s, bool held, float score_dn, int64_t capture_ns,
                      FramePrediction& out);
  void report(FramePrediction& out) const;  // report_embedding: copies the embedding + int8 tensor

  const Model& model_;
  Executor& executor_;
  ProcessorOptions options_;
  std::vector<Sensor> sensors_;
  heads::HeadEvaluator heads_;
  std::vector<int16_t> reported_;
  std::vector<float> embedding_;
  std::vector<float> difference_image_;  // a finger's frame for the tracker (difference_plan)
  int32_t int8_tensor_ = -1;             // report_embedding: the int8 tensor reported (-1: none)
  std::unique_ptr<GraspTracker> tracker_;
  size_t grasp_head_ = 0;
  ProcessorCounters counters_;
};

}  // namespace tlvlink::pipeline
