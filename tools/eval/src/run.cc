// evaluate_files and fit_heads_into_file (run.h).

#include "tlvlink/eval/run.h"

#include <memory>

#include "tlvlink/eval/trust.h"
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

Result<BoundRow> evaluate_bound(const std::string& spec, const EvalData& data,
                                const EvalOptions& options) {
  const size_t eq = spec.find('=');
  TLV_ENSURE(eq != std::string::npos && eq > 0 && eq + 1 < spec.size(), ErrorCode::kInvalidArgument,
             "--bound '%s': expected LABEL=MODEL.tlvm", spec.c_str());
  BoundRow b;
  b.label = spec.substr(0, eq);
  b.model_path = spec.substr(eq + 1);
  EvalOptions o = options;
  o.model_heads = true;
  o.zero_shot = ZeroShotSource::kModel;
  o.oracle_samples = 0;
  o.touch_oracles = false;
  TLV_ASSIGN_OR_RETURN(const EvalReport r, evaluate_one(b.model_path, data, o));
  b.model_name = r.model_name;
  for (Task t : kAllTasks) {
    const TaskResult* heads = r.find(t, Method::kModelHeads);
    const TaskResult* probe = r.find(t, Method::kProbe);
    if (heads != nullptr && heads->available)
      b.results.push_back(*heads);
    else if (probe != nullptr)
      b.results.push_back(*probe);
  }
  return b;
}

Result<EvalRun> run_eval(const EvalJob& job) {
  EvalRun run;
  TLV_ASSIGN_OR_RETURN(EvalReport first, evaluate_one(job.model_path, job.data, job.options));
  for (const std::string& spec : job.bounds) {
    TLV_ASSIGN_OR_RETURN(BoundRow b, evaluate_bound(spec, job.data, job.options));
    first.bounds.push_back(std::move(b));
  }
  run.reports.push_back(std::move(first));
  if (!job.compare_path.empty()) {
    EvalOptions o = job.options;
    o.oracle_samples = 0;  // the data is the same: one oracle estimate serves both
    TLV_ASSIGN_OR_RETURN(EvalReport r, evaluate_one(job.compare_path, job.data, o));
    r.oracle = run.reports.front().oracle;
    run.reports.push_back(std::move(r));
  }
  if (!job.record_path.empty()) {
    TLV_ASSIGN_OR_RETURN(std::unique_ptr<Model> model, tools::load_model(job.model_path));
    TrustRecordOptions ro;
    ro.drop_untrusted_zero_shot = !job.keep_untrusted_zero_shot;
    TLV_ASSIGN_OR_RETURN(const std::vector<std::byte> bytes,
                         model_with_trust(*model, run.reports.front(), ro, &run.trust_lines));
    TLV_TRY(tools::write_file(job.record_path, bytes));
  }
  return run;
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
  TLV_ASSIGN_OR_RETURN(const std::vector<std::byte> bytes, model_with_heads(*model, out.heads, wo));
  // Score what will be written, as the device applies it (the model's heads on the test split),
  // and record that score in the heads (trust.h) before the file is written.
  TLV_ASSIGN_OR_RETURN(const std::unique_ptr<Model> written, Model::load(bytes));
  EvalOptions score = job.options;
  score.fit_probes = false;
  score.model_heads = true;
  score.oracle_samples = 0;
  score.touch_oracles = false;
  TLV_ASSIGN_OR_RETURN(out.score, evaluate_embeddings(written->metadata(), set, score));
  out.score.touch_dir = job.data.touch_dir;
  out.score.grasp_dir = job.data.grasp_dir;
  TrustRecordOptions ro;
  ro.drop_untrusted_zero_shot = !job.keep_untrusted_zero_shot;
  TLV_ASSIGN_OR_RETURN(const std::vector<std::byte> recorded,
                       model_with_trust(*written, out.score, ro, &out.trust_lines));
  TLV_TRY(tools::write_file(job.output_path, recorded));
  out.bytes = recorded.size();
  return out;
}

}  // namespace tlvlink::eval
