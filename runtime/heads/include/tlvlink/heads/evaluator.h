#pragma once
// A model's stored heads evaluated on its embeddings, allocation-free per frame: the per-frame
// heads (linear probes and zero-shot prompt matrices) on one embedding, the press heads on a
// press's peak and first embeddings, and the grasp head on the embeddings of both fingers that
// its layout names.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/metadata.h"

namespace tlvlink::heads {

enum class HeadKind : uint8_t { kProbe = 0, kZeroShot = 1, kPress = 2 };
const char* head_kind_name(HeadKind kind);  // "probe", "zero-shot", "press"

// One per-frame head's result; spans point into the evaluator (valid until the next evaluate)
// and names/labels into the model (valid while the Model lives).
struct HeadResult {
  std::string_view name;
  HeadKind kind = HeadKind::kProbe;
  std::span<const std::string_view> labels;
  std::span<const float> logits, probabilities;
  int32_t top = 0;  // argmax
  // The head's trust record in the model (never null; `present` false when unmeasured):
  // head_trust.h decides from it whether the head is shown by default.
  const HeadTrust* trust = nullptr;
};

// Whether a head is reported when none are named (the daemon's default output): a probe or press
// head that its trust record does not mark untrusted (head_trust.h). Heads without a record
// (older model files) are reported; zero-shot heads only when named.
bool reported_by_default(const HeadResult& result);

class HeadEvaluator {
 public:
  HeadEvaluator() = default;
  HeadEvaluator(const HeadEvaluator&) = delete;  // results_ point into scratch_
  HeadEvaluator& operator=(const HeadEvaluator&) = delete;
  HeadEvaluator(HeadEvaluator&&) = default;  // a moved vector keeps its buffer
  HeadEvaluator& operator=(HeadEvaluator&&) = default;

  // Borrows `metadata` (the Model's) for the evaluator's lifetime. Allocates every buffer.
  // Checks each head's shapes against the embedding dimension (kModelInvalidMetadata).
  static Result<HeadEvaluator> create(const Metadata& metadata);

  int32_t embedding_dim() const { return dim_; }

  // The per-frame heads on one embedding (embedding_dim values). No allocation.
  Status evaluate(std::span<const float> embedding);
  // Every head's latest result: the per-frame heads (linear, then zero-shot, in file order),
  // then the press heads (kind kPress), whose results evaluate_press() sets.
  std::span<const HeadResult> results() const { return results_; }
  size_t per_frame_count() const { return per_frame_; }  // results()[per_frame_count()..]: press

  // The press heads on a press's features (metadata.h kPressFeatures): its peak embedding and
  // its first frame's (embedding_dim values each). No allocation.
  bool has_press() const { return results_.size() > per_frame_; }
  Status evaluate_press(std::span<const float> peak, std::span<const float> first);

  // The grasp heads, if the model has one: the features their layout names, in layout order.
  // Head 0 is the model's grasp head (fitted on every sensor); heads 1.. its sensor grasp heads
  // (Metadata::sensor_grasp_heads, same layout), each fitted on one sensor model's grasps.
  bool has_grasp() const { return !grasp_layout_.empty(); }
  size_t grasp_head_count() const;
  // The head for fingers of `sensor_model` (capture/sensor_models.h names): the sensor grasp
  // head that names it, else 0. Also 0 for an empty name.
  size_t grasp_head_for(std::string_view sensor_model) const;
  const GraspHead& grasp_head(size_t head = 0) const;  // head < grasp_head_count()
  std::string_view grasp_name(size_t head = 0) const;
  const HeadTrust& grasp_trust(size_t head = 0) const { return grasp_head(head).trust; }
  std::span<const GraspFeature> grasp_layout() const { return grasp_layout_; }
  // p(success) of grasp head `head` from one feature per layout entry (an embedding of
  // embedding_dim values, or a finger's kDifferenceFeatures difference statistics). No
  // allocation.
  Result<float> grasp_probability(std::span<const std::span<const float>> features,
                                  size_t head = 0) const;

 private:
  const Metadata* metadata_ = nullptr;
  int32_t dim_ = 0;
  std::vector<HeadResult> results_;
  std::vector<float> scratch_;         // logits then probabilities of every head, back to back
  std::vector<size_t> offsets_;        // where each head's logits start in scratch_
  size_t per_frame_ = 0;               // results_ before the press heads
  std::vector<float> press_features_;  // [peak, peak - first]
  std::vector<GraspFeature> grasp_layout_;
};

// How logs and checks name grasp head `head`: "grasp", or "grasp (fitted on gelsight-mini)" for
// a sensor grasp head. Allocates: for start-up messages, not the frame loop.
std::string grasp_head_label(const HeadEvaluator& heads, size_t head);

}  // namespace tlvlink::heads
