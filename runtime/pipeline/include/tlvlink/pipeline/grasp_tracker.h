#pragma once
// One grasp prediction per grasp, from both fingers' embeddings at the moments the model's grasp
// head reads ("A.before,A.during,B.before,B.during"). Pure logic: frames and commands go in, a
// decision per grasp comes out; the caller runs the encoder and the grasp head.
//
// The moments mean what they mean in the Feel data the grasp head was trained on (and in the
// simulator's episodes): "before" the fingers are open, "during" they hold the object still
// resting on the table, "after" the object has been lifted. So a grasp is predicted before the
// lift, when the robot can still decide not to lift.
//
// Per grasp:
//   start    detected: both fingers touch, their contact onsets within onset_window
//            commanded: the controller's "closed" mark
//   before   each finger's latest frame without contact before the start (the tracker keeps
//            each finger's two latest encoded open-gel frames, refreshed every idle_refresh
//            while idle, no older than before_max_age at the start; when the newest carries a
//            later time than the "closed" mark, that finger's camera clock runs ahead of the
//            controller's, and the one before it is taken: an open gel either way)
//   during   each finger's first frame at or after start + settle (commanded: or at the
//            "lifting" mark if that comes first: the object no longer rests after it)
//   after    each finger's first frame at or after the later "during" frame + after_delay
//            detected, or the "lifting" mark + after_delay commanded
// Each finger's frames carry their own timestamps (two cameras are not synchronised): the two
// frames of the "during" and "after" moments must lie within pair_tolerance of each other, or
// the grasp is "not computed" with the reason ("before" frames show an open gel and need not be
// simultaneous). So is a grasp whose finger stops sending frames (frame_timeout), a finger that
// lets go before its frames were taken (detected), a finger with no open-gel frame to stand for
// "before", or a grasp superseded by a new "closed" mark. Never a made-up value.
//
// The tracker stores the embeddings it needs (wants() tells the caller which frames must be
// encoded even when contact gating would skip them). A layout with a finger's "difference"
// (heads/grasp_difference.h) also needs that finger's "before" and "during" frames as images:
// the model's crop and resize in DN, passed beside the embedding (wants_image() says for which
// fingers); the tracker computes the statistics when the grasp completes. Made once; no
// allocation per frame.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/heads/grasp_difference.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/pipeline/predictions.h"

namespace tlvlink::pipeline {

struct GraspOptions {
  enum class Mode : uint8_t { kDetected = 0, kCommanded = 1 };
  Mode mode = Mode::kDetected;
  int64_t onset_window_ns = 500'000'000;  // detected: both onsets within this make a grasp
  int64_t settle_ns = 300'000'000;        // start -> "during" (the grip has settled)
  int64_t after_delay_ns = 600'000'000;   // "during" (detected) or "lifting" (commanded) -> "after"
  int64_t idle_refresh_ns = 500'000'000;  // while idle, encode one open-gel frame this often
  int64_t before_max_age_ns = 10'000'000'000;  // an older open-gel frame cannot stand for "before"
  // The fingers' frames of one moment must lie this close. Each finger takes its first frame at
  // or after the moment, so two unsynchronised cameras are up to one frame period apart: the
  // default covers a 25 fps sensor (40 ms) plus jitter; a dropped frame exceeds it.
  int64_t pair_tolerance_ns = 50'000'000;
  int64_t frame_timeout_ns = 500'000'000;  // a finger silent this long past a moment: not computed
};
Status validate(const GraspOptions& options);
const char* grasp_mode_name(GraspOptions::Mode mode);  // "detected", "commanded"

// The images a layout's difference features are computed on (height x width x 3, DN).
struct GraspImageShape {
  int32_t height = 0, width = 0, channels = 0;
};

class GraspTracker {
 public:
  // `images` is needed (and checked) only when the layout has a difference feature.
  static Result<GraspTracker> create(std::span<const heads::GraspFeature> layout,
                                     int32_t embedding_dim, const GraspOptions& options,
                                     GraspImageShape images = {});

  // True when this finger's frame at t_ns will be taken for a moment: encode it.
  bool wants(int32_t finger, int64_t t_ns) const;
  // True when this finger's encoded frames without contact, and those wants() asks for, must
  // come with their image (the layout has this finger's difference).
  bool wants_image(int32_t finger) const;
  size_t image_values() const { return image_values_; }

  // Every frame of both fingers, each finger's in time order. `embedding` is empty when the
  // encoder did not run; `contact` is the contact gate's decision; `image` (image_values()
  // values, or empty) as wants_image() asks.
  void on_frame(int32_t finger, uint64_t sequence, int64_t t_ns, bool contact,
                std::span<const float> embedding, std::span<const float> image = {});
  // Time passes without frames (a camera gone): times out moments that are waiting.
  void tick(int64_t now_ns);

  // The controller's marks (commanded mode; ignored in detected mode, which returns false).
  bool mark_closed(int64_t t_ns);
  bool mark_lifting(int64_t t_ns);

  // The oldest finished grasp: its record (computed = false with the reason, or true: ready for
  // the grasp head, probability not yet set) and, when computed, its feature_count features in
  // layout order (spans into the tracker, valid until the next take_finished). False when none
  // is waiting.
  // Up to kMaxFinished grasps wait; older ones beyond that are dropped and counted.
  bool take_finished(GraspPrediction& out, std::span<const float> (&features)[kMaxGraspFeatures]);
  static constexpr int32_t kMaxFinished = 4;
  uint64_t finished_dropped() const { return finished_dropped_; }

  uint64_t grasps_started() const { return next_id_ - 1; }

 private:
  enum class Phase : uint8_t { kIdle, kWaiting, kFinished };
  struct Slot {
    bool taken = false;
    uint64_t sequence = 0;
    int64_t t_ns = 0;
  };

  void start(int64_t t_ns);
  void finish(bool computed, int64_t now_ns);
  [[gnu::format(printf, 3, 4)]] void fail(int64_t now_ns, const char* reason_format, ...);
  int64_t target(heads::Moment moment) const;  // -1 while unknown
  bool needed(int32_t finger, heads::Moment moment) const;
  bool image_needed(int32_t finger, heads::Moment moment) const;
  float* image_slot(int32_t finger, heads::Moment moment);  // before or during
  void check_complete(int64_t now_ns);
  void reset_grasp();

  std::vector<heads::GraspFeature> layout_;
  std::vector<size_t> offsets_;  // where each feature starts in a finished grasp's values
  size_t feature_values_ = 0;    // all features' values
  int32_t dim_ = 0;
  GraspOptions options_;
  std::vector<float> embeddings_;  // [finger][moment][dim]
  Slot slots_[heads::kFingers][heads::kMoments];
  bool contact_[heads::kFingers] = {false, false};
  // Each finger's two latest encoded open-gel frames (the candidates for "before"), stored in
  // idle_: the cameras' clocks are not the marks', so the newest may carry a time after the
  // "closed" mark that arrives later, and the one before it is then the finger's "before".
  static constexpr int32_t kIdleHistory = 2;
  Slot idle_slots_[heads::kFingers][kIdleHistory];
  int32_t idle_newest_[heads::kFingers] = {0, 0};
  std::vector<float> idle_;  // [finger][history][dim]
  // Difference features: the images of "before" and "during" and each finger's idle frames.
  bool difference_[heads::kFingers] = {false, false};
  size_t image_values_ = 0;
  std::vector<float> images_;       // [finger][before, during][image_values_]
  std::vector<float> idle_images_;  // [finger][history][image_values_]
  heads::GraspDifference difference_stats_;
  std::array<float, heads::kFingers * heads::kDifferenceFeatures> differences_{};
  int64_t onset_[heads::kFingers] = {-1, -1};
  int64_t last_frame_[heads::kFingers] = {-1, -1};
  Phase phase_ = Phase::kIdle;
  bool lifting_marked_ = false;
  int64_t start_ns_ = 0, lifting_ns_ = 0;
  uint64_t next_id_ = 1;
  std::array<char, kMaxReason> reason_{};  // the failure fail() is about to record
  // Finished grasps waiting to be taken: a ring of records and their features.
  std::array<GraspPrediction, kMaxFinished> finished_{};
  std::vector<float> finished_features_;  // [kMaxFinished][feature_values_]
  int32_t finished_head_ = 0, finished_count_ = 0;
  uint64_t finished_dropped_ = 0;
};

}  // namespace tlvlink::pipeline
