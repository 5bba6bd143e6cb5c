// tlvlink infer MODEL --input X.npy|X.ppm|X.jpg|X.png [--output Y.npy]: one inference, outputs as
// .npy or a summary.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "cli/common.h"
#include "cli/trust_text.h"
#include "tlvlink/io/file.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/png.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/verify/compare.h"
#include "tlvlink/io/npy_image.h"

namespace tlvlink::cli {
namespace {

struct InferOptions {
  std::string model, input, output;
  ExecutorFlags exec;
  bool compare_executors = false;
};

bool starts_with(const std::vector<std::byte>& b, std::string_view prefix) {
  return b.size() >= prefix.size() && std::memcmp(b.data(), prefix.data(), prefix.size()) == 0;
}

// Fills graph input 0 from a .npy tensor (used as-is), or a uint8 .npy, PPM/PGM, JPEG or PNG image
// (preprocessed per the model's InputSpec). The format is told by the file's magic bytes.
Status load_input(const std::string& path, const Model& model, std::span<std::byte> dst) {
  const Graph& g = model.graph();
  const Tensor& in = g.tensor(g.inputs[0]);
  TLV_ASSIGN_OR_RETURN(
      std::vector<std::byte> bytes,
      tools::read_file(path, tools::kMaxNpyDataBytes + tools::kMaxNpyHeaderBytes + 16));
  tools::Image image;
  if (starts_with(bytes, "\x93NUMPY")) {
    TLV_ASSIGN_OR_RETURN(tools::NpyArray a, tools::parse_npy(bytes, path));
    const bool image_like = a.dtype == DType::kUInt8 && in.dtype != DType::kUInt8;
    if (!image_like) {
      const bool same_shape = a.shape.size() == in.shape.rank &&
                              std::equal(a.shape.begin(), a.shape.end(), in.shape.dims.begin());
      // Float models also take uint8 images: the hint helps when one was saved as int8/float32.
      TLV_ENSURE(a.dtype == in.dtype && same_shape, ErrorCode::kShapeMismatch,
                 "%s: %s tensor of shape %s does not match model input '%.*s' %s %s%s",
                 path.c_str(), dtype_name(a.dtype), tools::npy_shape_string(a.shape).c_str(),
                 static_cast<int>(in.name.size()), in.name.data(), dtype_name(in.dtype),
                 shape_string(in.shape).c_str(),
                 in.dtype == DType::kFloat32 ? " (images: uint8 [H,W,C] or [1,H,W,C])" : "");
      std::memcpy(dst.data(), a.data.data(), dst.size());
      return {};
    }
    TLV_ASSIGN_OR_RETURN(image, tools::image_from_npy(a, path));
  } else if (starts_with(bytes, "P6") || starts_with(bytes, "P5")) {
    TLV_ASSIGN_OR_RETURN(image, tools::parse_pnm(bytes, path));
  } else if (starts_with(bytes, "\xff\xd8\xff")) {
    TLV_ASSIGN_OR_RETURN(image, image::decode_jpeg(std::span<const uint8_t>(
                                                       reinterpret_cast<const uint8_t*>(bytes.data()),
                                                       bytes.size()),
                                                   path));
  } else if (starts_with(bytes, "\x89PNG\r\n\x1a\n")) {
    TLV_ASSIGN_OR_RETURN(image, tools::read_png(path));
  } else {
    return Error::make(ErrorCode::kFormat,
                       "%s: neither a .npy file nor a PPM/PGM (binary), JPEG or PNG image",
                       path.c_str());
  }
  TLV_ENSURE(in.dtype == DType::kFloat32, ErrorCode::kModelUnsupported,
             "model input is %s; images can only feed float inputs", dtype_name(in.dtype));
  auto x = image::preprocess(image, model.metadata().input);
  if (!x.ok()) return x.error().with_context("%s", path.c_str());
  TLV_ENSURE(x->size() * sizeof(float) == dst.size(), ErrorCode::kShapeMismatch,
             "%s: preprocessing gave %zu values, model input %s needs %zu", path.c_str(), x->size(),
             shape_string(in.shape).c_str(), dst.size() / sizeof(float));
  std::memcpy(dst.data(), x->data(), dst.size());
  return {};
}

std::string output_path(const std::string& base, size_t i) {
  if (i == 0) return base;
  const size_t dot = base.rfind(".npy");
  return (dot == std::string::npos ? base : base.substr(0, dot)) + "." + std::to_string(i) + ".npy";
}

void print_summary(const Model& model, const Executor& exec) {
  const Graph& g = model.graph();
  for (size_t i = 0; i < g.outputs.size(); ++i) {
    const Tensor& t = g.tensor(g.outputs[i]);
    const std::vector<float> v = output_as_floats(t, exec.output(i));
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    double sum = 0;
    for (float f : v) sum += static_cast<double>(f);
    std::printf("output %zu '%.*s' %s %s: min %.5g max %.5g mean %.5g\n  first:", i,
                static_cast<int>(t.name.size()), t.name.data(), dtype_name(t.dtype),
                shape_string(t.shape).c_str(), static_cast<double>(*lo), static_cast<double>(*hi),
                sum / static_cast<double>(v.size()));
    for (size_t k = 0; k < std::min<size_t>(8, v.size()); ++k)
      std::printf(" %.5g", static_cast<double>(v[k]));
    std::printf("\n");
    const Metadata& m = model.metadata();
    if (static_cast<int32_t>(i) != m.embedding_output || m.embedding_dim <= 0 ||
        v.size() != static_cast<size_t>(m.embedding_dim)) {
      continue;
    }
    auto heads = heads::HeadEvaluator::create(m);
    if (heads.ok() && heads->evaluate(v).ok()) {
      for (const heads::HeadResult& r : heads->results()) {
        const auto top = static_cast<size_t>(r.top);
        std::printf("head %-14.*s %-9s -> %-18.*s p=%.3f  [%s]\n",
                    static_cast<int>(r.name.size()), r.name.data(), heads::head_kind_name(r.kind),
                    static_cast<int>(r.labels[top].size()), r.labels[top].data(),
                    static_cast<double>(r.probabilities[top]), trust_text(*r.trust, false).c_str());
      }
    }
    if (m.grasp_head.present) {
      std::printf("head %-14.*s %-9s -> needs %zu embeddings (%.*s); not computed from one frame"
                  "  [%s]\n",
                  static_cast<int>(m.grasp_head.name.size()), m.grasp_head.name.data(), "probe",
                  m.grasp_head.weight.size() / static_cast<size_t>(m.embedding_dim),
                  static_cast<int>(m.grasp_head.feature_layout.size()),
                  m.grasp_head.feature_layout.data(), trust_text(m.grasp_head.trust, false).c_str());
    }
    if (m.provenance.training.find("random-reference") != std::string_view::npos) {
      std::printf(
          "note: this model is the random reference encoder; its predictions are meaningless\n");
    }
  }
}

// Runs the same input through the other executor and checks every output against the rule of
// runtime/verify (the same as `verify`); exit 1 when an output is out of tolerance.
int compare_with_other_executor(const InferOptions& o, const Model& m, const Executor& first) {
  ExecutorFlags other = o.exec;
  other.executor = first.kind() == ExecutorKind::kXnnpack ? "reference" : "xnnpack";
  auto exec = create_executor(m, other);
  if (!exec.ok()) return report_error("infer", exec.error());
  Executor& e = **exec;
  if (Status s = load_input(o.input, m, e.input(0)); !s.ok())
    return report_error("infer", s.error());
  if (Status s = e.invoke(); !s.ok()) return report_error("infer", s.error());
  const Graph& g = m.graph();
  bool all_pass = true;
  for (size_t i = 0; i < g.outputs.size(); ++i) {
    const Tensor& t = g.tensor(g.outputs[i]);
    const std::vector<float> got = output_as_floats(t, first.output(i));
    const std::vector<float> want = output_as_floats(t, e.output(i));
    const verify::OutputComparison c = verify::compare_output(g, g.outputs[i], got, want);
    all_pass = all_pass && c.pass;
    std::printf("output %zu: %s vs %s executor: max abs difference %.4g", i,
                executor_kind_name(first.kind()), executor_kind_name(e.kind()), c.max_abs_error);
    if (c.error_in_lsb >= 0) std::printf(" (%.3g LSB)", c.error_in_lsb);
    std::printf(", tolerance %.4g (%s): %s\n", c.tolerance, c.rule, c.pass ? "PASS" : "FAIL");
  }
  return all_pass ? kExitOk : kExitFailure;
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
  if (Status s = load_input(o.input, m, e.input(0)); !s.ok())
    return report_error("infer", s.error());
  const auto t0 = std::chrono::steady_clock::now();
  if (Status s = e.invoke(); !s.ok()) return report_error("infer", s.error());
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!o.output.empty()) {
    const Graph& g = m.graph();
    for (size_t i = 0; i < g.outputs.size(); ++i) {
      const Tensor& t = g.tensor(g.outputs[i]);
      tools::NpyArray a;
      a.dtype = t.dtype;
      a.shape.assign(t.shape.dims.begin(),
                     t.shape.dims.begin() + static_cast<std::ptrdiff_t>(t.shape.rank));
      const std::span<const std::byte> out = e.output(i);
      a.data.assign(out.begin(), out.end());
      const std::string path = output_path(o.output, i);
      if (Status s = tools::write_npy(path, a); !s.ok()) return report_error("infer", s.error());
      std::printf("wrote %s (%s %s)\n", path.c_str(), dtype_name(t.dtype),
                  shape_string(t.shape).c_str());
    }
    return o.compare_executors ? compare_with_other_executor(o, m, e) : kExitOk;
  }
  std::printf("%s executor, %d thread(s), invoke %.3f ms\n", executor_kind_name(e.kind()),
              o.exec.threads, ms);
  print_summary(m, e);
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
         "[1,H,W,C], or a PPM/PGM (binary), JPEG or PNG image; images are resized and normalised "
         "per the model's input spec")
      ->required();
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
