#pragma once
// tlvlink_trainer: TLV-Link training of an edge touch encoder with libtorch, and its export to a
// float .tlvm. This header has no libtorch types, so the CLI and the tests compile without the
// (slow) torch headers. See tools/trainer/README.md.
//
//   TrainOptions o;
//   o.data_dir = "/tmp/t100k";       // Touch100k layout (tlvlink sim touch100k)
//   o.output = "/tmp/small.ckpt";
//   auto summary = train(o);          // pre-trains the vision teacher, then the student
//   ExportOptions e{.checkpoint = "/tmp/small.ckpt", .output = "/tmp/small.tlvm"};
//   auto exported = export_model(e);

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/metadata.h"
#include "tlvlink/trainer/schedule.h"

namespace tlvlink::trainer {

// Decoded, resized images are cached in memory once (uint8); more than this is an error that
// names the size needed (--max-cache-mb raises it). 4 GiB holds ~58k samples at 96x128 with
// their vision images.
inline constexpr size_t kDefaultMaxCacheBytes = size_t{4} << 30;
inline constexpr int32_t kMaxBatch = 4096;
inline constexpr int32_t kMaxThreads = 64;
// The test share of the datasets' default split (datasets::kDefaultSplit; options.cc checks).
inline constexpr double kDefaultTestFraction = 0.2;

struct TextOptions {
  std::string embeddings_dir;  // precomputed embeddings (text_encoder.h layout); empty: hashing
  int32_t dim = 128;           // hashing encoder only (precomputed: the files' D)
  uint64_t seed = 7;           // hashing encoder only
};

struct TeacherOptions {
  // Empty: the built-in teacher (a `builtin_arch` CNN pre-trained on the vision images against
  // the same text features, then frozen). Else a TorchScript vision encoder (torch::jit::load)
  // taking float [N, 3, input_height, input_width] RGB, (pixel/255 - mean) / std, and returning
  // [N, D_t] (a projection D_t -> text dim is learned with the student when D_t differs).
  std::string torchscript;
  std::string builtin_arch = "tiny";
  int32_t epochs = 3;  // built-in teacher pre-training epochs
  double lr = 1e-3;    // built-in teacher peak learning rate (trained from scratch)
  int32_t input_height = 224, input_width = 224;                     // TorchScript teacher input
  std::vector<float> mean = {0.48145466f, 0.4578275f, 0.40821073f};  // CLIP's, TorchScript only
  std::vector<float> std = {0.26862954f, 0.26130258f, 0.27577711f};
};

// What the student learns from (README "Objectives"):
//   kTlvLink            TLV-Link: symmetric InfoNCE of the (curriculum-mixed) embedding against
//                       the text features. The default and the method the product implements.
//   kSupervised         cross-entropy on the labels a simulated set records (material,
//                       hard/soft, rough/smooth; supervised.h) and nothing else: no text, no
//                       teacher. The supervised upper bound of the issue-16 tables.
//   kTlvLinkSupervised  both: InfoNCE + supervised_weight * cross-entropy (a multi-task
//                       objective beside TLV-Link; the curriculum applies to the InfoNCE part).
// Both supervised objectives add contact_weight * the contact regression (log force, friction)
// where the sidecar records them.
enum class Objective : uint8_t { kTlvLink = 0, kSupervised, kTlvLinkSupervised };
const char* objective_name(Objective objective);  // "tlv-link", "supervised", "tlv-link+supervised"
Result<Objective> parse_objective(std::string_view name);

// Photometric augmentation of the touch frames, drawn per sample and step from the seed (0 =
// off). It imitates what differs between two sensors of one model (tools/sim/REFERENCE.md "Sensor
// instances"): each colour channel is scaled by exp(N(0, gain_sigma)) around its frame mean
// (LED and white-balance gains), the frame by exp(N(0, exposure_sigma)), and N(0, noise_dn)
// camera noise is added; then rounded and clamped to uint8 like a camera frame.
struct AugmentOptions {
  double gain_sigma = 0;
  double exposure_sigma = 0;
  double noise_dn = 0;
  bool enabled() const { return gain_sigma > 0 || exposure_sigma > 0 || noise_dn > 0; }
};

// The sensor-view augmentation (README "Sensor-view augmentation"): what real sensors and links
// change in the frames of one touch, applied to each training frame at the sensor's processed
// size, before the model's own resize. Each component is drawn on or off per view with its
// probability and its parameters from the ranges in the README (view_augment.cc holds them).
enum ViewComponent : uint32_t {
  kViewGeometry = 1u << 0,  // mounting: shift, rotation, scale
  kViewColour = 1u << 1,    // LED / white-balance gains, exposure, colour cast
  kViewVignette = 1u << 2,  // radial fall-off
  kViewLedDrift = 1u << 3,  // a colour gradient across the gel
  kViewDust = 1u << 4,      // dark specks on the gel or lens
  kViewBlur = 1u << 5,      // focus
  kViewNoise = 1u << 6,     // sensor noise
  kViewCodec = 1u << 7,     // none, JPEG q50-98, MJPEG decoded at 1/2 or 1/4, YUYV 4:2:2
  kViewAll = (1u << 8) - 1,
};
// "geometry", "colour", ... for one bit; a comma list for a mask ("none" for 0, "all").
std::string view_components_name(uint32_t components);
// "all", "none" or a comma list of the names above; kInvalidArgument naming an unknown one.
Result<uint32_t> parse_view_components(std::string_view list);

struct ViewAugmentOptions {
  uint32_t components = 0;  // ViewComponent bits; 0 = off
  // > 0: two views of every sample per step, both in the losses, plus this weight times the
  // mean (1 - cosine) between the two views' embeddings (needs components).
  double consistency_weight = 0;
  // > 0 with two views and the supervised heads: this weight times the heads' disagreement
  // between the views (symmetric KL of each head's distributions, squared difference of the
  // contact read-out). The cosine term treats every direction of the embedding alike; this one
  // holds still the directions the answers are read from.
  double prediction_weight = 0;
  // With two views: the share of samples whose second view is the first one's codec twin (the
  // same view through another codec draw, ViewAugmenter::make_codec_twin), so that the
  // consistency terms also see pairs that differ by the link alone, as a frame and its
  // re-encoding do; the rest get two independent views. 0 = every pair independent.
  double codec_pairs = 0;
  // The size the views are made at: the sensors' processed frame (every profile's is 240x320).
  int32_t frame_height = 240, frame_width = 320;
  bool enabled() const { return components != 0; }
};

struct TrainOptions {
  std::string data_dir;        // Touch100k-format directory
  std::string output;          // final checkpoint (required)
  std::string checkpoint_dir;  // periodic checkpoints step_NNNNNNN.ckpt (empty: none)
  int64_t checkpoint_every = 500;
  std::string resume;    // checkpoint to continue from (its settings are used)
  std::string log_path;  // JSON-lines training log; empty: <output>.log.jsonl

  std::string arch = "small";
  int32_t input_height = 96, input_width = 128;
  ResizeFilter resize = ResizeFilter::kBilinear;
  TextOptions text;
  TeacherOptions teacher;
  BetaOptions beta;  // schedule kNone = --no-curriculum (no teacher needed)
  Objective objective = Objective::kTlvLink;
  double supervised_weight = 1;  // kTlvLinkSupervised: weight of the cross-entropy term
  // With the supervised heads (kSupervised, kTlvLinkSupervised): weight of the contact
  // regression beside the cross-entropy, a linear read-out of the frame's log normal force and
  // the material's friction coefficient from the embedding (supervised.h). 0 = off. The grasp
  // head needs both linearly in the embedding: success is mostly friction x grip force against
  // the object's weight (firmware/models/README.md "Accuracy and ceilings", the grasp target).
  double contact_weight = 1;
  AugmentOptions augment;
  ViewAugmentOptions view;

  LrOptions lr;
  double weight_decay = 0.2;  // AdamW, on conv/FC weights (not BN, biases, temperature)
  double adam_beta1 = 0.9, adam_beta2 = 0.98, adam_eps = 1e-6;
  double init_temperature = 0.07;
  double max_logit_scale = 100;  // CLIP's clamp of 1 / temperature
  int32_t batch = 96;
  int32_t epochs = 12;
  int64_t max_steps = 0;  // > 0: train this many steps (schedules span them) instead
  uint64_t seed = 1;
  int32_t threads = 1;      // torch intra-op threads (results depend on it; see README)
  int64_t max_samples = 0;  // > 0: use only the first N training samples
  size_t max_cache_bytes = kDefaultMaxCacheBytes;
  // The hash split by session of a set that records none (the datasets' rule,
  // tlvlink/datasets/detect.h).
  double test_fraction = kDefaultTestFraction;
};
// Checks ranges and combinations; names the offending setting (kInvalidArgument).
Status validate(const TrainOptions& options);

struct TrainSummary {
  std::string arch_description;  // describe_arch()
  int64_t train_samples = 0;
  int64_t steps = 0, start_step = 0, steps_per_epoch = 0;
  double first_epoch_loss = 0, last_epoch_loss = 0, final_loss = 0;
  double student_samples_per_s = 0;
  double load_seconds = 0, teacher_seconds = 0, student_seconds = 0;
  std::string checkpoint;  // the final checkpoint written
  std::string log_path;
};
Result<TrainSummary> train(const TrainOptions& options);

struct ExportOptions {
  std::string checkpoint;
  std::string output;           // .tlvm
  std::string text_embeddings;  // override the recorded precomputed-embeddings directory
  std::string name;             // model name; empty: "tlvlink-<arch>-<h>x<w>-fp32"
  // Golden I/O pairs embedded in the model (`tlvlink verify` replays them on the board): the
  // first `golden_frames` test-split touch frames of `golden_data` (empty: the checkpoint's
  // training set, skipped with a note when it no longer exists), preprocessed by
  // tools::preprocess, with libtorch's eval-mode embeddings as the expected outputs.
  std::string golden_data;
  int32_t golden_frames = 2;  // 0..8
};
inline constexpr int32_t kMaxGoldenFrames = 8;
struct ExportSummary {
  std::string arch_description;
  uint64_t macs = 0;
  size_t file_bytes = 0;
  int32_t embedding_dim = 0;
  std::vector<std::string> zero_shot_heads;
  int32_t golden_pairs = 0;
  std::string note;  // e.g. why no golden pairs were embedded
};
// Folds BatchNorm, writes the fp32 .tlvm with metadata and zero-shot heads, and checks that it
// loads (Model::load).
Result<ExportSummary> export_model(const ExportOptions& options);

// --- Inspection hooks (tests, parity) ---

// What a checkpoint records: the JSON settings/provenance and the step it was taken at.
struct CheckpointInfo {
  std::string meta_json;
  int64_t step = 0, total_steps = 0;
  InputSpec input;  // spans point into `mean` / `std`
  std::vector<float> mean, std;
  std::string arch;
};
Result<CheckpointInfo> read_checkpoint_info(const std::string& path);

// The student's embeddings in libtorch, eval mode: `nhwc` is n preprocessed frames [n,H,W,3]
// (tools::preprocess output), result [n, embedding_dim], not normalised.
Result<std::vector<float>> libtorch_embeddings(const std::string& checkpoint,
                                               std::span<const float> nhwc, int64_t n);

// Symmetric InfoNCE of n pairs (rows of x and y, each [n, dim], L2-normalised here):
// logits = scale * x y^T, loss = (CE(logits, diag) + CE(logits^T, diag)) / 2.
Result<double> info_nce_loss(std::span<const float> x, std::span<const float> y, int64_t n,
                             int64_t dim, double logit_scale);

}  // namespace tlvlink::trainer
