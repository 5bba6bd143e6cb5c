#pragma once
// Flags shared by `tlvlink eval` and `tlvlink heads fit`: datasets, split, executor, probe fitting,
// zero-shot source. Turned into tlvlink::eval's EvalData / EvalOptions.

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "common.h"
#include "tlvlink/eval/eval.h"

namespace tlvlink::cli {

struct EvalFlags {
  std::string touch, touch_format = "auto";
  std::string grasp, grasp_format = "auto";
  std::string problems;  // --problems FILE: every load problem
  double resplit = -1;   // < 0: recorded split for generated sets, hash split otherwise
  uint64_t split_seed = 0;
  int64_t max_touch = 0, max_grasp = 0;
  std::vector<int32_t> train_jpeg;
  bool train_live = false;
  std::string touch_from_grasps;
  std::vector<std::string> view_weights;  // --view-weight: W or TASK=W items; empty = {0}
  double min_view_agreement = 0;
  int jpeg_scale = 1;
  int quarter_turns = 0;
  std::string grasp_features = "before-during-difference";
  std::string l2_grid;  // comma-separated; empty: the library's default grid
  int max_iterations = 300;
  std::string zero_shot = "auto";
  std::string text_embeddings;
  int64_t text_seed = -1;  // < 0: the model's recorded text encoder (else seed 7)
  int64_t oracle_samples = 10000;
  bool quiet = false;
  ExecutorFlags exec;

  void add_to(CLI::App& app);
  Result<eval::EvalData> data() const;
  Result<eval::EvalOptions> options() const;

 private:
  Status parse_view_weights(eval::HeadFitOptions& heads) const;
};

}  // namespace tlvlink::cli
