#pragma once
// A press head (metadata.h kPressFeatures: a contact's peak embedding and its change from the
// first frame) fitted from recorded presses: scenarios of single-finger presses (`tlvlink sim
// scenario --grasps 0`: truth.jsonl) that tlvlinkd played with `embedding = true`. Each press's
// frames in contact go, in order, through the board's own pipeline::PressTracker, so the head is
// fitted on exactly the features the board computes. Validated by grouped cross-validation with
// the recordings as groups (every fold scores presses of a scenario, and of sensor instances, it
// did not fit), against a baseline of the same fit on the peak alone (what one frame shows): the
// head's trust record keeps both, and a head that does not beat one frame is not trusted.
//
//   auto fit = eval::fit_press_head(model, {"press-401", "press-402", ...}, {});
//   auto bytes = eval::model_with_press_head(model, fit->head);  // replaces or adds the head

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/grouped_cv.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::eval {

inline constexpr const char* kOneFrameBaseline =
    "the same fit on the press's peak alone (one frame's view)";

struct PressHeadOptions {
  std::string head = "hard_soft_press";  // the head's name
  // The scenario's event label it learns (truth.jsonl events), and the per-frame head whose label
  // order it takes (when the model has one; else the labels seen, sorted).
  std::string label = "hard_soft";
  // tlvlinkd's outputs in each recording's folder: one play of the scenario per file (e.g. its
  // live path and its exact frames: two views of every press, grouped by the folder).
  std::vector<std::string> predictions = {"press.jsonl"};
  CvOptions cv;
};

// One row per press and play in which the gate saw it for at least PressTracker::kMinFrames
// frames: its features at the contact's last frame (when a contact of the press broke, its
// longest one).
struct PressRows {
  int32_t dim = 0;                  // embedding dimension
  std::vector<float> features;      // [presses, 2 * dim]: peak, peak - first
  std::vector<float> peaks;         // [presses, dim]: the baseline's view
  std::vector<int32_t> labels;      // index into `classes`
  std::vector<std::string> groups;  // the recording (folder) of each press, whichever play
  std::vector<int32_t> press;       // the press's event in its recording (same in every play)
  std::vector<std::string> classes;
  std::vector<std::string> sensors;  // each recording's sensor model, in `recordings` order
  std::vector<std::string> recordings;
  int64_t presses = 0;               // labelled press events, times the plays of each
  int64_t short_presses = 0;         // of them, seen for fewer frames (or not at all): not rows
  int64_t distinct_presses() const;  // presses with a row in at least one play
};

// Errors name the folder and line: a missing or unreadable truth.jsonl / predictions file, a
// recording without embeddings, or one made with another encoder (its hello's model checksum).
Result<PressRows> read_recorded_presses(const Model& model, const std::vector<std::string>& dirs,
                                        const PressHeadOptions& options);

struct PressHeadFit {
  PressRows rows;
  CvResult head_cv, baseline_cv;
  quantize::LinearHeadSpec head;  // fitted on every press, features kPressFeatures, trust set
  double l2 = 0;
};

// Errors: those of read_recorded_presses and cross_validate (e.g. one recording: nothing to
// validate on an unseen one), an empty head name or one a per-frame head has.
Result<PressHeadFit> fit_press_head(const Model& model, const std::vector<std::string>& dirs,
                                    const PressHeadOptions& options);

// The copy of `model` with `head` among its press heads (one of the same name is replaced).
Result<std::vector<std::byte>> model_with_press_head(const Model& model,
                                                     const quantize::LinearHeadSpec& head,
                                                     bool* replaced = nullptr);

// The report: presses per recording and class, head and one-frame baseline cross-validated.
std::string format_press_head(const PressHeadFit& fit);

}  // namespace tlvlink::eval
