// tlvlink export: checkpoint -> folded fp32 .tlvm with zero-shot heads; libtorch inspection hooks.

#include <torch/utils.h>

#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "checkpoint.h"
#include "data_cache.h"
#include "export_graph.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/model.h"
#include "tlvlink/text/text_encoder.h"
#include "tlvlink/trainer/trainer.h"

namespace tlvlink::trainer {
namespace {

std::vector<float> to_vector(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
  return {c.data_ptr<float>(), c.data_ptr<float>() + c.numel()};
}

PlainNet to_plain(EncoderNet& net) {
  PlainNet p;
  p.arch = net->spec();
  for (size_t i = 0; i < net->convs.size(); ++i) {
    const torch::Tensor& w = net->convs[i]->weight;
    PlainLayer l;
    l.shape = {static_cast<int32_t>(w.size(0)), static_cast<int32_t>(w.size(1)),
               static_cast<int32_t>(w.size(2)), static_cast<int32_t>(w.size(3))};
    l.weight_oihw = to_vector(w);
    const auto& bn = net->norms[i];
    l.bn.gamma = to_vector(bn->weight);
    l.bn.beta = to_vector(bn->bias);
    l.bn.running_mean = to_vector(bn->running_mean);
    l.bn.running_var = to_vector(bn->running_var);
    l.bn.eps = static_cast<float>(bn->options.eps());
    p.layers.push_back(std::move(l));
  }
  p.fc_weight = to_vector(net->fc->weight);
  p.fc_bias = to_vector(net->fc->bias);
  return p;
}

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string s;
  for (const std::string& p : parts) s += (s.empty() ? "" : sep) + p;
  return s;
}

Result<quantize::ZeroShotHeadSpec> zero_shot_head(text::TextEncoder& encoder,
                                                  const text::PromptSet& prompts) {
  quantize::ZeroShotHeadSpec h;
  h.name = prompts.task;
  h.class_names = prompts.class_names;
  h.prompt_template = prompts.templates.empty() ? join(prompts.fixed_prompts, " | ")
                                                : join(prompts.templates, " | ");
  auto m = text::zero_shot_matrix(encoder, prompts);
  if (!m.ok()) return m.error().with_context("zero-shot head '%s'", prompts.task.c_str());
  h.prompt_matrix = std::move(m).value();
  h.logit_scale = 100.0f;  // the paper's zero-shot scale (datasets-and-method.md)
  return h;
}

Result<std::unique_ptr<text::TextEncoder>> encoder_for(const nlohmann::ordered_json& meta,
                                                       const std::string& override_dir) {
  try {
    const auto& t = meta.at("text_encoder");
    const std::string dir =
        override_dir.empty() ? t.at("embeddings_dir").get<std::string>() : override_dir;
    std::unique_ptr<text::TextEncoder> enc;
    if (dir.empty()) {
      TLV_ASSIGN_OR_RETURN(
          enc, text::make_hashing_text_encoder(
                   {.dim = t.at("dim").get<int32_t>(), .seed = t.at("seed").get<uint64_t>()}));
      // The same settings must give the same encoder; a changed implementation would make the
      // prompt matrix disagree with the space the student was trained in.
      const std::string recorded = t.at("description").get<std::string>();
      TLV_ENSURE(enc->description() == recorded, ErrorCode::kInvalidState,
                 "the checkpoint was trained with text encoder '%s', this build has '%s'",
                 recorded.c_str(), enc->description().c_str());
    } else {
      TLV_ASSIGN_OR_RETURN(enc, text::open_precomputed_text_embeddings(dir));
    }
    TLV_ENSURE(enc->dim() == meta.at("arch").at("embedding_dim").get<int32_t>(),
               ErrorCode::kInvalidArgument, "text encoder dim %d != the model's embedding dim %d",
               enc->dim(), meta.at("arch").at("embedding_dim").get<int32_t>());
    return enc;
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "checkpoint text_encoder record: %s", e.what());
  }
}

// Golden pairs: test-split frames through tools::preprocess, libtorch eval outputs.
Status add_golden(const ExportOptions& o, const nlohmann::ordered_json& meta, EncoderNet& net,
                  quantize::MetadataSpec& m, ExportSummary& summary) {
  TLV_ENSURE(o.golden_frames >= 0 && o.golden_frames <= kMaxGoldenFrames,
             ErrorCode::kInvalidArgument, "golden frames %d outside 0..%d", o.golden_frames,
             kMaxGoldenFrames);
  if (o.golden_frames == 0) return {};
  std::string dir = o.golden_data;
  if (dir.empty()) {
    dir = meta.at("dataset").at("dir").get<std::string>();
    struct stat st {};
    if (::stat((dir + "/data_list.json").c_str(), &st) != 0) {
      summary.note += (summary.note.empty() ? "" : "; ") +
                      std::string(
                          "no golden pairs: the "
                          "training set ") +
                      dir + " is gone (pass --golden-data DIR)";
      return {};
    }
  }
  CacheOptions co;
  co.dir = dir;
  co.split = SplitChoice::kTest;
  co.touch_height = m.input.height;
  co.touch_width = m.input.width;
  co.load_vision = false;
  co.max_samples = o.golden_frames;
  co.test_fraction = meta.at("settings").at("test_fraction").get<double>();
  auto cache = load_cache(co);
  if (!cache.ok()) return cache.error().with_context("golden frames");
  InputSpec spec;
  spec.height = m.input.height;
  spec.width = m.input.width;
  spec.channels = 3;
  spec.mean = m.input.mean;
  spec.std = m.input.std;
  net->eval();
  torch::NoGradGuard no_grad;
  for (const std::string& key : cache->keys) {
    const std::string path = dir + "/touch/" + key;
    TLV_ASSIGN_OR_RETURN(tools::Image image, tools::read_jpeg(path));
    auto x = image::preprocess(image, spec);
    if (!x.ok()) return x.error().with_context("golden frame %s", path.c_str());
    const torch::Tensor in =
        torch::from_blob(x->data(), {1, spec.height, spec.width, 3}, torch::kFloat32)
            .permute({0, 3, 1, 2})
            .contiguous();
    const std::vector<float> y = to_vector(net->forward(in));
    const auto* xb = reinterpret_cast<const std::byte*>(x->data());
    const auto* yb = reinterpret_cast<const std::byte*>(y.data());
    m.golden.emplace_back(std::vector<std::byte>(xb, xb + x->size() * sizeof(float)),
                          std::vector<std::byte>(yb, yb + y.size() * sizeof(float)));
  }
  summary.golden_pairs = static_cast<int32_t>(m.golden.size());
  return {};
}

// The sensor profiles a simulated set records in its tlvlink_sim.json (generator.sensor: a name
// or a comma list); empty when it is gone or says nothing.
std::vector<std::string> sensors_of_set(const std::string& dir) {
  std::vector<std::string> out;
  std::ifstream in(dir + "/tlvlink_sim.json");
  if (!in) return out;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("generator") || !j["generator"].is_object()) return out;
  const nlohmann::json& g = j["generator"];
  if (!g.contains("sensor") || !g["sensor"].is_string()) return out;
  const std::string list = g["sensor"].get<std::string>();
  for (size_t start = 0; start <= list.size();) {
    const size_t comma = std::min(list.find(',', start), list.size());
    if (comma > start) out.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

Result<ExportSummary> export_model(const ExportOptions& o) {
  TLV_ENSURE(!o.checkpoint.empty() && !o.output.empty(), ErrorCode::kInvalidArgument,
             "export needs a checkpoint and an output path");
  TLV_ASSIGN_OR_RETURN(TrainState state, load_checkpoint(o.checkpoint));
  const nlohmann::ordered_json& meta = state.meta;
  const PlainNet plain = to_plain(state.student);
  const ArchSpec& arch = plain.arch;

  quantize::ModelBuilder b;
  TLV_ASSIGN_OR_RETURN(const uint64_t macs, add_student_graph(plain, b));
  quantize::MetadataSpec& m = b.metadata();
  m.name = !o.name.empty() ? o.name
                           : "tlvlink-" + arch.name + "-" + std::to_string(arch.input_height) +
                                 "x" + std::to_string(arch.input_width) + "-fp32";
  m.input.height = arch.input_height;
  m.input.width = arch.input_width;
  m.input.channels = 3;
  m.input.channel_order = ChannelOrder::kRGB;
  try {
    // Checkpoints before issue 29 record "bilinear" (or nothing) and were trained that way.
    m.input.resize_filter = meta.at("input").value("resize", std::string("bilinear")) == "area"
                                ? ResizeFilter::kArea
                                : ResizeFilter::kBilinear;
    m.input.mean = meta.at("input").at("mean").get<std::vector<float>>();
    m.input.std = meta.at("input").at("std").get<std::vector<float>>();
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: input normalisation: %s", o.checkpoint.c_str(),
                       e.what());
  }
  m.embedding_dim = arch.embedding_dim;
  m.embedding_output = 0;

  auto encoder = encoder_for(meta, o.text_embeddings);
  if (!encoder.ok()) return encoder.error().with_context("%s", o.checkpoint.c_str());
  ExportSummary summary;
  // A student trained on labels alone never saw the text space: zero-shot heads would only
  // measure chance, so that model gets none.
  const std::string objective =
      meta.at("settings").value("objective", std::string(objective_name(Objective::kTlvLink)));
  if (objective == objective_name(Objective::kSupervised)) {
    summary.note = "no zero-shot heads: objective supervised does not align with the text";
  } else {
    for (const text::PromptSet& p : {text::material_prompts(), text::hardness_prompts(),
                                     text::roughness_prompts(), text::grasp_prompts()}) {
      TLV_ASSIGN_OR_RETURN(quantize::ZeroShotHeadSpec h, zero_shot_head(**encoder, p));
      summary.zero_shot_heads.push_back(h.name);
      m.zero_shot_heads.push_back(std::move(h));
    }
  }
  // Linear probes and the grasp head are fitted later on runtime embeddings (tlvlink heads fit).
  m.producer = "tlvlink export";
  // The camera views the model learnt (tlvlink infer checks a frame's sensor against them).
  // Checkpoints written before they were recorded: the training set's own description.
  nlohmann::ordered_json dataset = meta.at("dataset");
  if (!dataset.contains("sensors")) dataset["sensors"] = sensors_of_set(dataset.value("dir", ""));
  nlohmann::ordered_json training = {
      {"kind", objective},
      {"trained", true},
      {"checkpoint", o.checkpoint},
      {"arch", meta.at("arch")},
      {"macs", macs},
      {"settings", meta.at("settings")},
      {"input", meta.at("input")},
      {"text_encoder", meta.at("text_encoder")},
      {"zero_shot_text_encoder", (*encoder)->description()},
      {"teacher", meta.at("teacher")},
      {"dataset", dataset},
      {"steps", meta.at("step")},
      {"total_steps", meta.at("total_steps")},
      {"epoch_losses", meta.at("epoch_losses")},
      {"final_loss", meta.at("last_loss")},
      {"final_temperature", meta.at("temperature")},
      {"checkpoint_written_utc", meta.at("written_utc")},
  };
  if (meta.contains("summary")) training["summary"] = meta.at("summary");
  m.training_json = training.dump();
  m.quantization_json = "{\"kind\":\"none\"}";
  try {
    TLV_TRY(add_golden(o, meta, state.student, m, summary));
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: golden pairs: %s", o.checkpoint.c_str(), e.what());
  }

  const std::vector<std::byte> bytes = b.finish();
  auto loaded = Model::load(bytes);
  if (!loaded.ok()) {
    return loaded.error().with_context("the exported model does not load (exporter bug)");
  }
  TLV_TRY(tools::write_file(o.output, bytes));
  summary.arch_description = describe_arch(arch);
  summary.macs = macs;
  summary.file_bytes = bytes.size();
  summary.embedding_dim = arch.embedding_dim;
  return summary;
}

Result<CheckpointInfo> read_checkpoint_info(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(TrainState state, load_checkpoint(path));
  CheckpointInfo info;
  try {
    info.meta_json = state.meta.dump();
    info.step = state.meta.at("step").get<int64_t>();
    info.total_steps = state.meta.at("total_steps").get<int64_t>();
    info.arch = state.meta.at("arch").at("name").get<std::string>();
    info.mean = state.meta.at("input").at("mean").get<std::vector<float>>();
    info.std = state.meta.at("input").at("std").get<std::vector<float>>();
    info.input.height = state.meta.at("input").at("height").get<int32_t>();
    info.input.width = state.meta.at("input").at("width").get<int32_t>();
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "%s: checkpoint meta: %s", path.c_str(), e.what());
  }
  info.input.channels = 3;
  info.input.mean = info.mean;
  info.input.std = info.std;
  return info;
}

Result<std::vector<float>> libtorch_embeddings(const std::string& checkpoint,
                                               std::span<const float> nhwc, int64_t n) {
  TLV_ASSIGN_OR_RETURN(TrainState state, load_checkpoint(checkpoint));
  const ArchSpec& a = state.student->spec();
  const size_t per_frame =
      static_cast<size_t>(a.input_height) * static_cast<size_t>(a.input_width) * 3;
  TLV_ENSURE(n >= 1 && nhwc.size() == per_frame * static_cast<size_t>(n), ErrorCode::kShapeMismatch,
             "%zu input values for %lld frames of %dx%dx3", nhwc.size(), static_cast<long long>(n),
             a.input_height, a.input_width);
  state.student->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::from_blob(const_cast<float*>(nhwc.data()),
                                           {n, a.input_height, a.input_width, 3}, torch::kFloat32)
                              .permute({0, 3, 1, 2})
                              .contiguous();
  return to_vector(state.student->forward(x));
}

Result<double> info_nce_loss(std::span<const float> x, std::span<const float> y, int64_t n,
                             int64_t dim, double logit_scale) {
  TLV_ENSURE(n >= 1 && dim >= 1 && x.size() == static_cast<size_t>(n * dim) &&
                 y.size() == static_cast<size_t>(n * dim),
             ErrorCode::kShapeMismatch, "x holds %zu and y %zu values for [%lld, %lld]", x.size(),
             y.size(), static_cast<long long>(n), static_cast<long long>(dim));
  torch::NoGradGuard no_grad;
  auto tx = torch::from_blob(const_cast<float*>(x.data()), {n, dim}, torch::kFloat32);
  auto ty = torch::from_blob(const_cast<float*>(y.data()), {n, dim}, torch::kFloat32);
  return clip_loss(tx, ty, torch::full({}, logit_scale, torch::kFloat32)).item<double>();
}

}  // namespace tlvlink::trainer
