// evaluate_files and fit_heads_into_file (run.h).

#include "tlvlink/eval/run.h"

#include <memory>

#include "tlvlink/io/file.h"
#include "tlvlink/io/model_file.h"

namespace tlvlink::eval {
namespace {

Result<EvalReport> evaluate_one(const std::string& path, const EvalData& data,
                                const EvalOptions& options) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, tools::load_model(path));
  auto report = evaluate(*model, data, options);
  if (!report.ok()) return report.error().with_context("evaluating %s", path.c_str());
  report->model_path = path;
  return std::move(report).value();
}

}  // namespace

Result<std::vector<EvalReport>> evaluate_files(std::span<const std::string> paths,
                                               const EvalData& data, const EvalOptions& options) {
  std::vector<EvalReport> reports;
  for (size_t i = 0; i < paths.size(); ++i) {
    EvalOptions o = options;
    if (i > 0) o.oracle_samples = 0;  // the data is the same: one oracle estimate serves all
    TLV_ASSIGN_OR_RETURN(EvalReport r, evaluate_one(paths[i], data, o));
    if (i > 0) r.oracle = reports.front().oracle;
    reports.push_back(std::move(r));
  }
  return reports;
}

Result<HeadsFitResult> fit_heads_into_file(const HeadsFitJob& job) {
  TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, tools::load_model(job.model_path));
  TLV_ASSIGN_OR_RETURN(const EmbeddingSet set,
                       extract_embeddings(*model, job.data, job.options.embedder));
  HeadsFitResult out;
  TLV_ASSIGN_OR_RETURN(out.heads, fit_heads(set, job.options.heads));
  if (job.on_note)
    for (const std::string& note : out.heads.notes) job.on_note(note);
  TLV_ENSURE(!out.heads.linear.empty() || out.heads.grasp, ErrorCode::kFormat,
             "no head could be fitted (no labelled training rows)");
  WriteHeadsOptions wo;
  wo.add_missing_zero_shot = job.add_missing_zero_shot;
  wo.text = job.options.text;
  wo.provenance_note = "tlvlink heads fit";
  if (!job.data.touch_dir.empty()) wo.provenance_note += " --touch " + job.data.touch_dir;
  if (!job.data.grasp_dir.empty()) wo.provenance_note += " --grasp " + job.data.grasp_dir;
  TLV_ASSIGN_OR_RETURN(const std::vector<std::byte> bytes,
                       model_with_heads(*model, out.heads, wo));
  TLV_TRY(tools::write_file(job.output_path, bytes));
  out.bytes = bytes.size();
  // Score what was written, as the device applies it (the model's heads on the test split).
  TLV_ASSIGN_OR_RETURN(const std::unique_ptr<Model> written, Model::load(bytes));
  EvalOptions score = job.options;
  score.fit_probes = false;
  score.model_heads = true;
  score.oracle_samples = 0;
  TLV_ASSIGN_OR_RETURN(out.score, evaluate_embeddings(written->metadata(), set, score));
  return out;
}

}  // namespace tlvlink::eval
