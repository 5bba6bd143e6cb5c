// fp32 vs int8 task accuracies through tools/eval: each model is evaluated on the same data and
// splits (probes fitted on each model's own train-split embeddings, heads as stored).

#include "tlvlink/quantize/task_compare.h"

#include <algorithm>

#include "tlvlink/eval/eval.h"

namespace tlvlink::quantize {

Result<TaskComparison> compare_tasks(const Model& fp32, const Model& quantized,
                                     const TaskEvalOptions& flags) {
  eval::EvalData data;
  data.touch_dir = flags.touch_dir;
  data.grasp_dir = flags.grasp_dir;
  eval::EvalOptions o;
  o.embedder.executor = ExecutorKind::kXnnpack;
  o.embedder.threads = flags.threads;
  auto a = eval::evaluate(fp32, data, o);
  if (!a.ok()) return a.error().with_context("evaluating the fp32 model");
  auto b = eval::evaluate(quantized, data, o);
  if (!b.ok()) return b.error().with_context("evaluating the quantized model");
  a->model_path = "fp32";
  b->model_path = "int8";
  const eval::EvalReport* reports[] = {&*a, &*b};
  TaskComparison out;
  out.table = eval::format_table(reports, /*paper_rows=*/false);
  out.json = nlohmann::json::parse(eval::report_json(reports), nullptr, /*allow_exceptions=*/false);
  for (const eval::TaskResult& r : a->results) {
    const eval::TaskResult* q = b->find(r.task, r.method);
    if (!r.available || q == nullptr || !q->available) continue;
    out.max_drop_points = std::max(out.max_drop_points, (r.accuracy - q->accuracy) * 100.0);
  }
  return out;
}

}  // namespace tlvlink::quantize
