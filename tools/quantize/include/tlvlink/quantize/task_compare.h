#pragma once
// Task accuracies of the float and the quantized model side by side (material, hard/soft,
// rough/smooth, grasp; linear probe, the model's heads, zero-shot) through the evaluation
// library (tools/eval).

#include <string>

#include <nlohmann/json.hpp>

#include "tlvlink/error.h"
#include "tlvlink/model.h"

namespace tlvlink::quantize {

struct TaskEvalOptions {
  std::string touch_dir;  // Touch100k / TAG dir (--eval-touch)
  std::string grasp_dir;  // Feel dir or .h5 (--eval-grasp)
  int threads = 1;
  bool requested() const { return !touch_dir.empty() || !grasp_dir.empty(); }
};

struct TaskComparison {
  std::string table;  // plain text, fp32 and int8 side by side
  nlohmann::json json;
  double max_drop_points = 0;  // largest fp32 - int8 accuracy drop over available cells, in points
};

// Evaluates both models on the same data with tools/eval (XNNPACK executor).
Result<TaskComparison> compare_tasks(const Model& fp32, const Model& quantized,
                                     const TaskEvalOptions& options);

}  // namespace tlvlink::quantize
