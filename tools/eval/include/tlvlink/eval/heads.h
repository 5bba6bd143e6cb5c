#pragma once
// Task heads fitted on runtime embeddings, zero-shot heads from a text encoder, and writing them
// into a copy of a model ("same graph, new metadata").
//
// Head semantics and arithmetic are the runtime's (runtime/heads, tlvlink/heads/head_math.h):
// evaluation scores exactly what the board computes.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/eval/probe.h"
#include "tlvlink/eval/tasks.h"
#include "tlvlink/metadata.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"

namespace tlvlink::eval {

// Which frames of a grasp episode feed the grasp probe.
enum class GraspFeatures : uint8_t {
  kBeforeDuring = 0,  // "A.before,A.during,B.before,B.during" (Calandra's predictor)
  kBeforeAfter,       // "A.before,A.after,B.before,B.after" (TLV-Link's released code)
  // before-during plus each finger's difference statistics (heads/grasp_difference.h): the
  // default ("A.before,A.during,A.difference,B.before,B.during,B.difference")
  kBeforeDuringDifference,
};
// "before-during" / "before-after" / "before-during-difference"
const char* grasp_features_name(GraspFeatures f);
Result<GraspFeatures> parse_grasp_features(std::string_view name);
std::string grasp_feature_layout(GraspFeatures f);

// p(gripping) logit of a grasp head on one episode: w . concat(frames per layout) + b
// (heads::grasp_logit on the episode's embeddings).
Result<float> grasp_head_logit(std::span<const float> weight, float bias,
                               std::string_view feature_layout, const GraspEmbeddings& set,
                               size_t episode);

// Text encoder for zero-shot heads a model does not carry.
struct TextOptions {
  std::string precomputed_dir;           // set: open_precomputed_text_embeddings(dir)
  std::optional<uint64_t> hashing_seed;  // set: the built-in hashing encoder, dim = embedding_dim
  // Neither set: the encoder recorded in the model's provenance.training ("text_encoder":
  // {"dim", "seed", "embeddings_dir"}, as `tlvlink export` writes it), else hashing seed 7.
};
inline constexpr uint64_t kDefaultHashingSeed = 7;
inline constexpr float kZeroShotLogitScale = 100.0f;  // the paper's zero-shot scale

// The four zero-shot heads from the paper's prompt templates through the text encoder, named and
// ordered like tools/text's prompt sets ("material", "hard", "rough", "grasp"; class i = label
// value i), logit scale 100 — the heads `tlvlink export` writes. Error when the encoder's dim
// differs from the model's embedding_dim.
struct TextHeads {
  std::vector<quantize::ZeroShotHeadSpec> heads;
  std::string encoder;  // TextEncoder::description()
};
Result<TextHeads> zero_shot_heads_from_text(const Metadata& metadata, const TextOptions& text);

struct HeadFitOptions {
  ProbeOptions probe;
  // A touch head's own view-weight grid, in place of probe.view_weight_grid (e.g. a 20-class
  // head that a codec penalty costs more accuracy than a two-class one).
  std::map<Task, std::vector<double>> view_weight_grid_of;
  // The heads to fit; empty = every one the data allows. A head not fitted keeps the model's.
  std::set<Task> only;
  GraspFeatures grasp_features = GraspFeatures::kBeforeDuringDifference;
  // The two fingers are alike (the simulator draws each on its own sensor; a real gripper's
  // fingers are interchangeable), so the grasp head is fitted on every training episode twice,
  // once with A and B swapped: the fit then gives both fingers the same weights, half the free
  // parameters for the same data.
  bool grasp_swap_fingers = true;
  // When the grasp set's training split holds several sensor models, also a grasp head per
  // model fitted on that model's episodes alone (metadata.h sensor_grasp_heads): one head for
  // every sensor is a compromise between their optics (firmware/models/README.md).
  bool grasp_per_sensor = true;
  // The heads' probes fitted side by side on up to this many threads (each probe's own fit is
  // serial); the heads are the same for any count.
  int32_t threads = 1;
};

// Probes fitted on the TRAIN split: linear heads named by task_name() with canonical labels,
// and a grasp head (two-class fit turned into w = w_true - w_false, b = b_true - b_false, which
// gives the same decision and probability). Tasks without training labels are left out (note).
struct FittedHeads {
  std::vector<quantize::LinearHeadSpec> linear;
  std::optional<quantize::GraspHeadSpec> grasp;
  std::vector<quantize::GraspHeadSpec> sensor_grasp;  // grasp_per_sensor: one per sensor model
  bool grasp_swap_fingers = false;                    // fitted with A/B-swapped copies
  std::vector<std::pair<Task, FittedProbe>> probes;   // diagnostics per fitted task
  std::vector<std::string> notes;                     // tasks skipped and why
};
Result<FittedHeads> fit_heads(const EmbeddingSet& set, const HeadFitOptions& options);

struct WriteHeadsOptions {
  bool replace_linear = true;  // fitted heads replace the model's heads of the same name
  bool replace_grasp = true;
  // Zero-shot heads for tasks the model has none for (from `text`); existing ones are kept.
  bool add_missing_zero_shot = true;
  TextOptions text;
  std::string provenance_note;  // appended to provenance.training as {"heads": ...} context
};
// The bytes of a copy of `model` with the heads in its metadata: same graph, constants,
// quantization and golden pairs (quantize/model_copy.h), so outputs are bit-identical.
Result<std::vector<std::byte>> model_with_heads(const Model& model, const FittedHeads& heads,
                                                const WriteHeadsOptions& options);

}  // namespace tlvlink::eval
