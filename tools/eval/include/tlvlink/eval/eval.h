#pragma once
// Task accuracy of a model: TLV-Link's Table 2 on runtime embeddings (host side, no libtorch).
// For each task (material, hard/soft, rough/smooth, grasp) and method:
//   probe        a linear probe fitted on the train split (probe.h), scored on the test split
//   model-heads  the linear / grasp heads stored in the model, as the device would apply them
//   zero-shot    argmax of cosine with the prompt matrix (the model's zero-shot heads, else
//                computed with tools/text); grasp averages logits over A/B x before/after
// Any .tlvm works (fp32, ONNX-imported, int8), so fp32 and int8 can be compared with this code:
//
//   EvalData data{.touch_dir = "/data/t100k", .grasp_dir = "/data/feel"};
//   auto fp32 = tlvlink::eval::evaluate(*fp32_model, data, {});
//   auto int8 = tlvlink::eval::evaluate(*int8_model, data, {});
//   for (const TaskResult& r : fp32->results) ... r.accuracy vs int8->find(r.task, r.method)
//   std::puts(format_table({&*fp32, &*int8}).c_str());
//
// Or extract once and evaluate the embeddings (e.g. to also compare them directly):
//   auto set = extract_embeddings(model, data, {});  evaluate_embeddings(model.metadata(), *set,
//   {});

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/eval/embeddings.h"
#include "tlvlink/eval/heads.h"
#include "tlvlink/eval/oracle.h"
#include "tlvlink/eval/probe.h"
#include "tlvlink/eval/tasks.h"
#include "tlvlink/metadata.h"
#include "tlvlink/model.h"

namespace tlvlink::eval {

enum class Method : uint8_t { kProbe = 0, kModelHeads, kZeroShot };
const char* method_name(Method method);   // "probe" / "model-heads" / "zero-shot"
const char* method_title(Method method);  // "linear probe" / "model's heads" / "zero-shot"

enum class ZeroShotSource : uint8_t {
  kAuto = 0,  // the model's zero-shot head for the task when present, else the text encoder
  kModel,     // only the model's heads (a task without one is reported unavailable)
  kText,      // always the text encoder (TextOptions)
};

struct EvalOptions {
  EmbedderOptions embedder;
  HeadFitOptions heads;  // probe fitting and grasp feature choice
  ZeroShotSource zero_shot = ZeroShotSource::kAuto;
  TextOptions text;
  bool fit_probes = true;   // fit and score linear probes (the "linear probe" row)
  bool model_heads = true;  // also score the heads stored in the model
  // Grasp oracle Monte Carlo episodes (~3 s); 0 skips it and the grasp frames estimate.
  int64_t oracle_samples = 10000;
  bool touch_oracles = true;  // oracle.h rows when the touch set records hidden variables
};

// One cell of the table.
struct TaskResult {
  Task task = Task::kMaterial;
  Method method = Method::kProbe;
  bool available = false;  // false: not evaluated, `note` says why
  double accuracy = 0;     // correct / n on the test split, in [0, 1]
  int64_t n = 0;           // test items scored
  int64_t correct = 0;
  std::vector<uint8_t> item_correct;  // 1 where labelled test item i (split order) was right
  int64_t unlabelled = 0;             // test items without a label for this task (not scored)
  double chance = 0;                  // 1 / classes (the paper's chance row)
  double majority = 0;  // accuracy of always predicting the test split's commonest class
  std::string
      source;  // e.g. "fit l2=0.01 (val 0.82)", "model head 'material'", "text hashing-v1(...)"
  std::string note;
};

struct GraspOracle {
  double accuracy = 0;  // Bayes-optimal on visible variables (tlvlink/sim/generate.h)
  double class_friction_accuracy = 0;  // the same with mu known only through the class
  double prior_friction_accuracy = 0;  // the same with mu not known at all (the grasp prior's)
  double success_rate = 0;
  double majority_rate = 0;
  int64_t samples = 0;
};

// A reference model's accuracy beside the evaluated one (`tlvlink eval --bound LABEL=MODEL`):
// e.g. the supervised upper bounds. Scored like the evaluated model's own heads when it has
// heads (fit both on the same heads' set), else by linear probes fitted on this data.
struct BoundRow {
  std::string label;  // "supervised tiny (same size)"
  std::string model_path, model_name;
  std::vector<TaskResult> results;  // Method::kModelHeads or kProbe, one per task

  const TaskResult* find(Task task) const;
};

struct EvalReport {
  std::string model_name;  // metadata name
  std::string model_path;  // set by the CLI
  std::string executor;
  std::vector<TaskResult> results;  // for each Method, each Task (kAllTasks order)
  std::optional<SplitInfo> touch_split, grasp_split;
  std::string touch_format,
      grasp_format;                  // "touch100k" / "touch_and_go"; "feel_hdf5" / "feel_repacked"
  std::string touch_dir, grasp_dir;  // the data evaluated on (evaluate() fills them)
  std::string touch_load_summary, grasp_load_summary;
  std::optional<GraspOracle> oracle;  // generated grasp sets only
  // Generated grasp sets with recorded variables only (oracle.h): on this test split.
  std::optional<GraspFramesOracle> grasp_frames_oracle;
  std::vector<TouchOracle> touch_oracles;  // generated touch sets with hidden variables only
  std::vector<BoundRow> bounds;            // reference models' probe rows (the CLI fills them)
  GraspFeatures grasp_features = GraspFeatures::kBeforeDuringDifference;
  double extract_seconds = 0, fit_seconds = 0;
  int64_t frames = 0;
  std::vector<std::pair<Task, FittedProbe>> probes;  // diagnostics of each fitted probe
  std::vector<std::string> notes;  // e.g. "the model is the random reference encoder ..."
  // A model with sensor grasp heads: its grasp head alone on every test episode, then each
  // sensor head on its sensor's (their trust records; n = 0 when the set holds none of that
  // sensor's episodes); the model-heads grasp cell in `results`
  // scores each episode by its sensor's head, as a runtime does. Empty otherwise.
  std::vector<TaskResult> grasp_head_cells;

  const TaskResult* find(Task task, Method method) const;
};

Result<EvalReport> evaluate_embeddings(const Metadata& metadata, const EmbeddingSet& set,
                                       const EvalOptions& options);
Result<EvalReport> evaluate(const Model& model, const EvalData& data, const EvalOptions& options);

// How two cells scored on the same test items disagree (e.g. fp32 vs int8): the items only the
// first / only the second got right, and the exact two-sided McNemar p of that split (the
// chance of a split at least this uneven if neither were better; 1 when they never disagree).
// An accuracy difference is 100 * (only_second - only_first) / n points: this says whether the
// items behind it are more than a coin could give. Fails when the cells scored different items.
struct Discordance {
  int64_t only_first = 0, only_second = 0;
  double p = 1;
};
Result<Discordance> discordance(const TaskResult& first, const TaskResult& second);

// The paper's Table 2 (real data), for the reference row. Accuracy in [0, 1].
struct PaperRow {
  const char* label;
  double material, hard, rough, grasp;
};
std::span<const PaperRow> paper_table2();

// Plain-text table like the paper's Table 2: one block of rows per report (probe, model heads,
// zero-shot; "n" under each cell), a chance row, the grasp oracle beside the grasp column, and
// the paper's rows labelled "paper (real data)". Several reports print side by side by row
// (e.g. fp32 / int8, with / without curriculum).
std::string format_table(std::span<const EvalReport* const> reports, bool paper_rows = true);
// The same as JSON (a document with "reports": [...], "paper": [...]).
std::string report_json(std::span<const EvalReport* const> reports);

}  // namespace tlvlink::eval
