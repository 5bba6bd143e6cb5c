// tlvlink infer MODEL --input X.npy|X.ppm|X.jpg|X.png [--output Y.npy]: one inference, outputs as
// .npy or a summary with the model's head predictions; --compare-executors runs the other
// executor too and compares every output (runtime/verify's rule). The input's format is told by
// its magic bytes and images are preprocessed by the model's input spec (tools/io model_input.h).

#include <algorithm>
#include <cstdio>

#include "common.h"
#include "tlvlink/bench/timing.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/inspect/trust_text.h"
#include "tlvlink/io/format.h"
#include "tlvlink/io/model_input.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/sensor_frame.h"
#include "tlvlink/verify/executors.h"

namespace tlvlink::cli {
namespace {

struct InferOptions {
  std::string model, input, output, sensor;
  ExecutorFlags exec;
  bool compare_executors = false;
};

std::string output_path(const std::string& base, size_t i) {
  if (i == 0) return base;
  const size_t dot = base.rfind(".npy");
  return (dot == std::string::npos ? base : base.substr(0, dot)) + "." + std::to_string(i) + ".npy";
}

std::vector<float> output_floats(const Tensor& t, std::span<const std::byte> bytes) {
  std::vector<float> v(t.shape.elements());
  for (size_t i = 0; i < v.size(); ++i) v[i] = verify::output_value(t, bytes, i);
  return v;
}

void print_heads(const Metadata& m, std::span<const float> embedding) {
  auto heads = heads::HeadEvaluator::create(m);
  if (heads.ok() && heads->evaluate(embedding).ok()) {
    for (const heads::HeadResult& r : heads->results().first(heads->per_frame_count())) {
      const auto top = static_cast<size_t>(r.top);
      std::printf("head %-14.*s %-9s -> %-18.*s p=%.3f  [%s]\n", static_cast<int>(r.name.size()),
                  r.name.data(), heads::head_kind_name(r.kind),
                  static_cast<int>(r.labels[top].size()), r.labels[top].data(),
                  static_cast<double>(r.probabilities[top]),
                  inspect::trust_text(*r.trust, false).c_str());
    }
  }
  if (m.grasp_head.present) {
    std::printf(
        "head %-14.*s %-9s -> needs %zu embeddings (%.*s); not computed from one frame"
        "  [%s]\n",
        static_cast<int>(m.grasp_head.name.size()), m.grasp_head.name.data(), "probe",
        m.grasp_head.weight.size() / static_cast<size_t>(m.embedding_dim),
        static_cast<int>(m.grasp_head.feature_layout.size()), m.grasp_head.feature_layout.data(),
        inspect::trust_text(m.grasp_head.trust, false).c_str());
    for (const GraspHead& g : m.sensor_grasp_heads) {
      std::string sensors;
      for (std::string_view v : g.sensors) sensors += (sensors.empty() ? "" : ",") + std::string(v);
      std::printf("head %-14.*s %-9s -> the grasp head for %s fingers  [%s]\n",
                  static_cast<int>(g.name.size()), g.name.data(), "probe", sensors.c_str(),
                  inspect::trust_text(g.trust, false).c_str());
    }
  }
  for (const LinearHead& h : m.press_heads) {
    std::printf("head %-14.*s %-9s -> needs a press (%.*s); not computed from one frame  [%s]\n",
                static_cast<int>(h.name.size()), h.name.data(), "press",
                static_cast<int>(h.features.size()), h.features.data(),
                inspect::trust_text(h.trust, false).c_str());
  }
  if (m.provenance.training.find("random-reference") != std::string_view::npos) {
    std::printf(
        "note: this model is the random reference encoder; its predictions are meaningless\n");
  }
}

void print_summary(const Model& model, const Executor& exec) {
  const Graph& g = model.graph();
  for (size_t i = 0; i < g.outputs.size(); ++i) {
    const Tensor& t = g.tensor(g.outputs[i]);
    const std::vector<float> v = output_floats(t, exec.output(i));
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    double sum = 0;
    for (float f : v) sum += static_cast<double>(f);
    std::printf("output %zu '%.*s' %s %s: min %.5g max %.5g mean %.5g\n  first:", i,
                static_cast<int>(t.name.size()), t.name.data(), dtype_name(t.dtype),
                tools::shape_string(t.shape).c_str(), static_cast<double>(*lo),
                static_cast<double>(*hi), sum / static_cast<double>(v.size()));
    for (size_t k = 0; k < std::min<size_t>(8, v.size()); ++k)
      std::printf(" %.5g", static_cast<double>(v[k]));
    std::printf("\n");
    const Metadata& m = model.metadata();
    if (static_cast<int32_t>(i) == m.embedding_output && m.embedding_dim > 0 &&
        v.size() == static_cast<size_t>(m.embedding_dim)) {
      print_heads(m, v);
    }
  }
}

Status write_outputs(const Model& m, const Executor& e, const std::string& base) {
  const Graph& g = m.graph();
  for (size_t i = 0; i < g.outputs.size(); ++i) {
    const Tensor& t = g.tensor(g.outputs[i]);
    const std::string path = output_path(base, i);
    TLV_TRY(tools::write_npy(path, tools::npy_from_tensor(t, e.output(i))));
    std::printf("wrote %s (%s %s)\n", path.c_str(), dtype_name(t.dtype),
                tools::shape_string(t.shape).c_str());
  }
  return {};
}

// The same input through the other executor, every output compared (exit 1 out of tolerance).
int compare_with_other_executor(const InferOptions& o, const Model& m, const Executor& first) {
  ExecutorFlags other = o.exec;
  other.executor = first.kind() == ExecutorKind::kXnnpack ? "reference" : "xnnpack";
  auto exec = create_executor(m, other);
  if (!exec.ok()) return report_error("infer", exec.error());
  Executor& e = **exec;
  std::string note;
  if (Status s = tools::load_sensor_input(o.input, o.sensor, m, e.input(0), note); !s.ok())
    return report_error("infer", s.error());
  if (Status s = e.invoke(); !s.ok()) return report_error("infer", s.error());
  const verify::ExecutorComparison c = verify::compare_executors(m, first, e);
  for (size_t i = 0; i < c.outputs.size(); ++i) {
    const verify::OutputComparison& r = c.outputs[i];
    std::printf("output %zu: %s vs %s executor: max abs difference %.4g", i,
                executor_kind_name(first.kind()), executor_kind_name(e.kind()), r.max_abs_error);
    if (r.error_in_lsb >= 0) std::printf(" (%.3g LSB)", r.error_in_lsb);
    std::printf(", tolerance %.4g (%s): %s\n", r.tolerance, r.rule, r.pass ? "PASS" : "FAIL");
  }
  return c.pass ? kExitOk : kExitFailure;
}

int run_infer(const InferOptions& o) {
  auto model = load_model(o.model);
  if (!model.ok()) return report_error("infer", model.error());
  const Model& m = **model;
  if (m.graph().inputs.size() != 1) {
    return report_error(
        "infer", Error::make(ErrorCode::kModelUnsupported, "model has %zu inputs; infer feeds one",
                             m.graph().inputs.size()));
  }
  auto exec = create_executor(m, o.exec);
  if (!exec.ok()) return report_error("infer", exec.error());
  Executor& e = **exec;
  std::string note;
  if (Status s = tools::load_sensor_input(o.input, o.sensor, m, e.input(0), note); !s.ok())
    return report_error("infer", s.error());
  if (!note.empty()) std::printf("%s\n", note.c_str());
  auto ms = bench::time_invoke(e);
  if (!ms.ok()) return report_error("infer", ms.error());
  if (!o.output.empty()) {
    if (Status s = write_outputs(m, e, o.output); !s.ok()) return report_error("infer", s.error());
  } else {
    std::printf("%s executor, %d thread(s), invoke %.3f ms\n", executor_kind_name(e.kind()),
                o.exec.threads, *ms);
    print_summary(m, e);
  }
  return o.compare_executors ? compare_with_other_executor(o, m, e) : kExitOk;
}

}  // namespace

void add_infer_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<InferOptions>();
  CLI::App* cmd = app.add_subcommand(
      "infer", "Run a model once on a tensor (.npy) or an image (.npy uint8, PPM/PGM, JPEG, PNG)");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  cmd->add_option(
         "--input,-i", o->input,
         "Input: float .npy shaped like the model input (used as-is), uint8 .npy image [H,W,C] or "
         "[1,H,W,C], or a PPM/PGM (binary), JPEG or PNG image; an image is read as a tactile "
         "sensor's processed view (a camera frame is cut to it as tlvlinkd cuts it; --sensor), "
         "then resized and normalised per the model's input spec")
      ->required();
  cmd->add_option("--sensor", o->sensor,
                  "The sensor the image comes from: " + tools::known_sensor_names() +
                      "; default: detected from its size (a camera frame of one sensor, or any "
                      "sensor's processed view); a frame of another size is refused unless 4:3");
  cmd->add_option(
      "--output,-o", o->output,
      "Write output 0 to this .npy (output i>0 to NAME.i.npy); default: print a summary");
  o->exec.add_to(*cmd);
  cmd->add_flag("--compare-executors", o->compare_executors,
                "Also run the other executor on the same input and compare every output (the "
                "tolerances of `verify`; exit 1 when out of tolerance)");
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_infer(*o); });
}

}  // namespace tlvlink::cli
