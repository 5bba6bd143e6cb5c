#pragma once
// A head of the user's own, from their own labelled frames (`tlvlink heads fit --images`):
// every frame is read as the sensor's processed view (tools/io sensor_frame.h: a camera frame is
// cut as tlvlinkd cuts it), embedded by the model exactly as the board would (the model's
// preprocessing and executor), and a linear head is fitted and validated by grouped
// cross-validation (grouped_cv.h). A baseline — the same logistic regression on the view's
// pixels, area-averaged to 32x24 RGB — is validated on the same folds: a head that does not beat
// it reads nothing the encoder adds, and its trust record says so (head_trust.h).
//
//   auto frames = eval::read_labelled_folder("billets/");
//   auto fit = eval::fit_user_head(model, *frames, {.head = "roughness"});
//   auto bytes = eval::model_with_user_head(model, fit->head);   // replaces or adds the head

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/eval/grouped_cv.h"
#include "tlvlink/eval/labelled_frames.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::eval {

inline constexpr int32_t kBaselineWidth = 32, kBaselineHeight = 24;
inline constexpr const char* kPixelBaseline =
    "logistic regression on the view's pixels, area-averaged to 32x24 RGB";

// The frames as the model and the baseline see them.
struct FrameFeatures {
  int32_t dim = 0;
  std::vector<float> embeddings;  // [frames, dim]
  std::vector<float> pixels;      // [frames, 32 * 24 * 3], in [0, 1]
  std::vector<int32_t> labels;
  std::vector<std::string> groups;
  std::vector<std::string> sensors;  // how each frame was read (its sensor; "" for none)
  std::string view_note;             // one line: the views the frames were read as
  double seconds = 0;                // reading and embedding
};

// `sensor`: a known sensor name, or empty to detect each frame's from its size. Errors name the
// frame (a size no sensor produces, decoding, the model).
Result<FrameFeatures> frame_features(const Model& model, const LabelledFrames& frames,
                                     const std::string& sensor, const EmbedderOptions& embedder);

struct UserHeadOptions {
  std::string head;    // the head's name (e.g. "roughness", "slip", "part_ok")
  std::string sensor;  // as frame_features
  CvOptions cv;
  EmbedderOptions embedder;
  bool learning_curve = false;  // also how accuracy grows with the groups per class
};

struct UserHeadFit {
  FrameFeatures features;
  CvResult head_cv, baseline_cv;
  std::vector<CurvePoint> head_curve, baseline_curve;  // when asked
  quantize::LinearHeadSpec head;  // fitted on every frame, labels = the class folders, trust set
  double l2 = 0;                  // the final fit's strength
  double fit_seconds = 0;         // validation and the final fit, head and baseline
};

// Errors: those of frame_features and cross_validate (a class with frames of one group only),
// an empty head name.
Result<UserHeadFit> fit_user_head(const Model& model, const LabelledFrames& frames,
                                  const UserHeadOptions& options);

// The copy of `model` with `head` in its metadata: a linear head of the same name is replaced,
// else it is added. Same graph and constants (quantize/model_copy.h). `replaced` (optional)
// tells which. Errors: the copy does not load.
Result<std::vector<std::byte>> model_with_user_head(const Model& model,
                                                    const quantize::LinearHeadSpec& head,
                                                    bool* replaced = nullptr);

// How a head the model already has does on labelled frames (`tlvlink eval --images`): every
// frame scored by the model's head, the folder's class names matched to the head's labels.
struct HeadScore {
  std::string head;
  int64_t n = 0, groups = 0;
  double accuracy = 0, ci_low = 0, ci_high = 0, balanced_accuracy = 0, majority = 0;
  std::vector<int64_t> predicted_counts;  // per head label: how often the head answered it
};
// Errors: no linear head of that name, a class folder that is not one of the head's labels.
Result<HeadScore> score_model_head(const Model& model, const FrameFeatures& features,
                                   const LabelledFrames& frames, const std::string& head,
                                   uint64_t seed = 0);

// A text report: the data (classes, rows and groups per class, grouping), head and baseline
// cross-validated with intervals, the majority rate, the curve when present, the times.
std::string format_user_head(const LabelledFrames& frames, const UserHeadFit& fit);

}  // namespace tlvlink::eval
