#pragma once
// Embeddings of a dataset as the runtime computes them: every frame goes through
// tools::preprocess (the model's InputSpec) and the chosen executor, and the model's embedding
// output (metadata.embedding_output, dequantized when int8) is kept. Works on any .tlvm with a
// float input 0 and an embedding output: fp32 trained, ONNX-imported, int8.
//
//   EmbedderOptions eo{.executor = ExecutorKind::kXnnpack, .threads = 2};
//   auto set = extract_embeddings(model, data, eo);   // streams the loaders, one frame in memory
//   // set->touch.row(i) is sample i's embedding, set->touch.material[i] its label

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/datasets/detect.h"
#include "tlvlink/datasets/report.h"
#include "tlvlink/datasets/split.h"
#include "tlvlink/error.h"
#include "tlvlink/eval/tasks.h"
#include "tlvlink/executor.h"
#include "tlvlink/heads/grasp_difference.h"
#include "tlvlink/heads/grasp_layout.h"
#include "tlvlink/model.h"
#include "tlvlink/sim/dataset.h"

namespace tlvlink::eval {

enum class TouchFormat : uint8_t { kAuto = 0, kTouch100k, kTouchAndGo };
enum class GraspFormat : uint8_t { kAuto = 0, kFeelHdf5, kFeelRepacked };

// Where the evaluation data lives. Empty dirs are skipped (at least one must be set).
// Formats and splits follow tools/datasets' one rule (tlvlink/datasets/detect.h): a dataset
// written by tlvlink's simulator keeps its recorded split (Touch100k: the sidecar's "split"; TAG:
// the train/test files; Feel: the recorded split). Any other dataset, or every dataset when
// `resplit` is set, is split by a hash of the session (touch) or object name (grasp) — never by
// frame, so train and test never share one.
struct EvalData {
  std::string touch_dir;
  TouchFormat touch_format =
      TouchFormat::kAuto;  // auto: data_list.json -> Touch100k, train.txt -> TAG
  std::string grasp_dir;   // a dir, or one calandra_corl2017_*.h5 file
  GraspFormat grasp_format = GraspFormat::kAuto;  // auto: *.h5 -> HDF5, train_info.json -> repacked
  std::optional<datasets::HashSplit> resplit;     // force a hash split
  datasets::HashSplit default_split = datasets::kDefaultSplit;  // when the data records none
  int32_t scale_denominator = 1;                                // JPEG decode at 1/1, 1/2, 1/4, 1/8
  int32_t gelsight_quarter_turns = 0;  // Feel HDF5: undo the stored rotation (0..3)
  // Touch TRAIN samples are also embedded after a JPEG re-encoding at each of these qualities
  // (extra train rows: same labels, same session), so probes fitted on them are fitted across
  // the codec paths a board's frames take (`--train-jpeg`). Test rows are never re-encoded.
  std::vector<int32_t> train_jpeg_qualities;
  // Touch TRAIN samples are also embedded after their sensor's live path (the simulated camera's
  // raw output decoded by the board's decoder: sim/live_path.h), a second view of each frame
  // (`--train-live`; simulated sets only: a sample must record its sensor).
  bool train_live_path = false;
  // A grasp set (Feel format, simulated: episodes record their object's material) whose TRAINING
  // episodes' "during" frames (both fingers) are also touch train rows: the touch heads then see
  // a gripper's contacts too, not only the touch set's presses (`--touch-from-grasps`).
  std::string touch_from_grasps_dir;
  // Caps per split (train and test each), for quick runs; 0 = all. Items beyond are not read.
  int64_t max_touch_samples = 0;
  int64_t max_grasp_episodes = 0;
  // Receives every load problem (the command shows and logs them); borrowed, may be null.
  datasets::ProblemEcho* problems = nullptr;
};

struct EmbedderOptions {
  ExecutorKind executor = ExecutorKind::kXnnpack;
  int threads = 1;
  bool progress = false;  // count/rate/ETA on stderr when it is a terminal
};

// Runs one model on single frames and returns its embedding. Owns its executor; borrows the
// model (which must outlive it).
class Embedder {
 public:
  // Errors: no embedding output (embedding_dim <= 0, embedding_output out of range, or the output
  // is not embedding_dim values), input 0 not float32, executor creation.
  static Result<std::unique_ptr<Embedder>> create(const Model& model,
                                                  const EmbedderOptions& options);
  ~Embedder();
  int32_t dim() const { return dim_; }
  const Model& model() const { return *model_; }
  // Preprocesses `frame` per the model's InputSpec, invokes, writes dim() floats into `out`.
  Status embed(const sim::RgbImage& frame, std::span<float> out);

 private:
  Embedder() = default;
  const Model* model_ = nullptr;
  std::unique_ptr<Executor> exec_;
  int32_t dim_ = 0;
};

// Where a split came from, for reports: "recorded", "hash(test_fraction=0.2, seed=0)".
struct SplitInfo {
  std::string source;
  int64_t train_items = 0, test_items = 0;
  int64_t train_groups = 0, test_groups = 0;  // sessions / objects
};

// Touch frames: row i of `values` is sample i's embedding. Labels use task class indices
// (tasks.h): -1 = no label for that task (rough: Sq between the smooth and rough thresholds;
// any task on a dataset without that label).
struct TouchEmbeddings {
  int32_t dim = 0;
  std::vector<float> values;       // [size(), dim]
  std::vector<int32_t> material;   // 0..19 or -1
  std::vector<int32_t> hard;       // 1 hard, 0 soft, or -1
  std::vector<int32_t> rough;      // 0 smooth, 1 rough, or -1
  std::vector<std::string> group;  // session
  std::vector<uint8_t> is_test;
  std::vector<std::string> keys;  // the loader's key of each sample
  // For a row that is a re-encoding of another (--train-jpeg, --train-live), that row's index; -1
  // for a frame as loaded. Empty when no row is re-encoded.
  std::vector<int64_t> view_of;
  // What the simulator recorded about each sample (its sidecar): the material's hidden
  // parameters and the contact. class_id -1 when the set records none (oracle.h needs them).
  std::vector<sim::MaterialSample> hidden_material;
  std::vector<sim::ContactState> hidden_contact;
  SplitInfo split;
  std::string format;        // "touch100k" / "touch_and_go"
  std::string load_summary;  // datasets::LoadReport::summary() of the loaders

  size_t size() const { return is_test.size(); }
  std::span<const float> row(size_t i) const {
    return std::span<const float>(values).subspan(i * static_cast<size_t>(dim),
                                                  static_cast<size_t>(dim));
  }
  // The labels of a touch task (material, hard or rough).
  const std::vector<int32_t>& labels(Task task) const {
    return task == Task::kMaterial ? material : task == Task::kHard ? hard : rough;
  }
};

// Grasp episodes: six embeddings each, [finger A, B] x [before, during, after].
inline constexpr int32_t kGraspFrames = heads::kFingers * heads::kMoments;
struct GraspEmbeddings {
  int32_t dim = 0;
  std::vector<float> values;  // [size(), kGraspFrames, dim], frame = finger * 3 + moment
  // Each finger's before-to-during difference features (heads/grasp_difference.h):
  // [size(), kFingers, kDifferenceFeatures]; empty when the model's input is not 3-channel.
  std::vector<float> difference;
  std::vector<int32_t> label;  // 1 gripping, 0 not
  // 1 where the episode's frames took the sensor's live path (sim feel --live-path[-fraction],
  // from its sidecar); 0 for the dataset's JPEG path and for sets that do not record it.
  std::vector<uint8_t> live_path;
  std::vector<std::string> group;  // object name
  // The sensor model both fingers carry ("gelsight-mini"; "" when the set does not record it).
  std::vector<std::string> sensor;
  std::vector<uint8_t> is_test;
  std::vector<std::string> keys;
  // What the simulator recorded about each episode (its sidecar): the grasp variables, the
  // object's material and each finger's "during" contact. class_id -1 when the set records none
  // (oracle.h's frames estimate needs them).
  std::vector<sim::GraspVariables> hidden_variables;
  std::vector<sim::MaterialSample> hidden_material;
  std::vector<std::array<sim::ContactState, heads::kFingers>> hidden_during;
  SplitInfo split;
  std::string format;  // "feel_hdf5" / "feel_repacked"
  std::string load_summary;
  // Generator options recorded in the dataset's tlvlink_sim.json (for the oracle), if any.
  std::optional<std::string> generator_json;

  size_t size() const { return is_test.size(); }
  std::span<const float> frame(size_t episode, int32_t finger, heads::Moment moment) const;
  std::span<const float> difference_of(size_t episode, int32_t finger) const;
  // The feature a grasp layout names (an embedding or a difference); empty when the set has no
  // differences.
  std::span<const float> feature(size_t episode, const heads::GraspFeature& f,
                                 int32_t finger_xor = 0) const;
};

struct EmbeddingSet {
  std::optional<TouchEmbeddings> touch;
  std::optional<GraspEmbeddings> grasp;
  double seconds = 0;  // wall time of the extraction (loading + preprocessing + invoke)
  int64_t frames = 0;  // frames run through the model
};

// Streams the datasets of `data` through `model`. Errors: a missing or unreadable dir, a format
// that cannot be detected, no labelled item at all, a model without an embedding output, an
// executor failure (naming the item's key). Skipped items (missing/corrupt files) are counted
// in load_summary, as the loaders do.
Result<EmbeddingSet> extract_embeddings(const Model& model, const EvalData& data,
                                        const EmbedderOptions& options);

}  // namespace tlvlink::eval
