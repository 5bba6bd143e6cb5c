// Validation and JSON form of the training settings.

#include <algorithm>
#include <cmath>

#include "options_json.h"
#include "tlvlink/datasets/detect.h"
#include "tlvlink/trainer/arch.h"

namespace tlvlink::trainer {
namespace {

// The default split of a set without a recorded one is the datasets' (one rule, one place).
static_assert(kDefaultTestFraction == datasets::kDefaultSplit.test_fraction);

}  // namespace

const char* objective_name(Objective o) {
  return o == Objective::kSupervised          ? "supervised"
         : o == Objective::kTlvLinkSupervised ? "tlv-link+supervised"
                                              : "tlv-link";
}

Result<Objective> parse_objective(std::string_view name) {
  for (Objective o : {Objective::kTlvLink, Objective::kSupervised, Objective::kTlvLinkSupervised}) {
    if (name == objective_name(o)) return o;
  }
  return Error::make(ErrorCode::kInvalidArgument,
                     "unknown objective '%.*s' (known: tlv-link, supervised, tlv-link+supervised)",
                     static_cast<int>(name.size()), name.data());
}

Status validate(const TrainOptions& o) {
  TLV_ENSURE(!o.data_dir.empty(), ErrorCode::kInvalidArgument, "no data directory given");
  TLV_ENSURE(!o.output.empty(), ErrorCode::kInvalidArgument, "no output checkpoint given (-o)");
  TLV_TRY(make_arch(o.arch, o.input_height, o.input_width, o.text.dim).status());
  // Nearest would alias every camera's noise and codec grain into the model (issue 29): the
  // trainer offers the two filters that average.
  TLV_ENSURE(o.resize == ResizeFilter::kBilinear || o.resize == ResizeFilter::kArea,
             ErrorCode::kInvalidArgument,
             "resize filter %s: the trainer resizes with bilinear or area",
             resize_filter_name(o.resize));
  TLV_TRY(validate(o.beta));
  TLV_ENSURE(o.objective != Objective::kSupervised || o.beta.schedule == BetaSchedule::kNone,
             ErrorCode::kInvalidArgument,
             "objective supervised has no text loss for a curriculum to act on: use it with "
             "--no-curriculum");
  TLV_ENSURE(
      std::isfinite(o.supervised_weight) && o.supervised_weight > 0 && o.supervised_weight <= 100,
      ErrorCode::kInvalidArgument, "supervised weight %g outside (0, 100]", o.supervised_weight);
  TLV_ENSURE(std::isfinite(o.contact_weight) && o.contact_weight >= 0 && o.contact_weight <= 100,
             ErrorCode::kInvalidArgument, "contact weight %g outside [0, 100]", o.contact_weight);
  const AugmentOptions& a = o.augment;
  TLV_ENSURE(a.gain_sigma >= 0 && a.gain_sigma <= 1 && a.exposure_sigma >= 0 &&
                 a.exposure_sigma <= 1 && a.noise_dn >= 0 && a.noise_dn <= 50,
             ErrorCode::kInvalidArgument,
             "augmentation gain sigma %g, exposure sigma %g (each in [0, 1]) or noise %g DN "
             "(in [0, 50]) out of range",
             a.gain_sigma, a.exposure_sigma, a.noise_dn);
  const ViewAugmentOptions& v = o.view;
  TLV_ENSURE((v.components & ~static_cast<uint32_t>(kViewAll)) == 0, ErrorCode::kInvalidArgument,
             "view augmentation components 0x%x: unknown bits", v.components);
  TLV_ENSURE(std::isfinite(v.consistency_weight) && v.consistency_weight >= 0 &&
                 v.consistency_weight <= 100,
             ErrorCode::kInvalidArgument, "consistency weight %g outside [0, 100]",
             v.consistency_weight);
  TLV_ENSURE(
      std::isfinite(v.prediction_weight) && v.prediction_weight >= 0 && v.prediction_weight <= 100,
      ErrorCode::kInvalidArgument, "prediction consistency weight %g outside [0, 100]",
      v.prediction_weight);
  TLV_ENSURE(
      v.prediction_weight == 0 || (v.consistency_weight > 0 && o.objective != Objective::kTlvLink),
      ErrorCode::kInvalidArgument,
      "a prediction consistency weight (%g) needs two views (--consistency-weight) and "
      "the supervised heads (objective supervised or tlv-link+supervised)",
      v.prediction_weight);
  TLV_ENSURE(std::isfinite(v.codec_pairs) && v.codec_pairs >= 0 && v.codec_pairs <= 1,
             ErrorCode::kInvalidArgument, "codec pairs %g outside [0, 1]", v.codec_pairs);
  TLV_ENSURE(v.codec_pairs == 0 || (v.consistency_weight > 0 && (v.components & kViewCodec)),
             ErrorCode::kInvalidArgument,
             "codec pairs (%g) need two views (--consistency-weight) and the codec view "
             "(--augment-view with codec)",
             v.codec_pairs);
  TLV_ENSURE(v.consistency_weight == 0 || v.enabled(), ErrorCode::kInvalidArgument,
             "a consistency weight (%g) needs the view augmentation (--augment-view): two views "
             "without it are the same frame",
             v.consistency_weight);
  TLV_ENSURE(!v.enabled() || (v.frame_height >= o.input_height && v.frame_width >= o.input_width &&
                              v.frame_height <= 4096 && v.frame_width <= 4096 &&
                              v.frame_width % 2 == 0 && v.frame_height % 2 == 0),
             ErrorCode::kInvalidArgument,
             "view frame %dx%d: at least the model input (%dx%d), at most 4096, even sides",
             v.frame_width, v.frame_height, o.input_width, o.input_height);
  TLV_TRY(validate(o.lr));
  TLV_ENSURE(o.weight_decay >= 0 && o.weight_decay < 10, ErrorCode::kInvalidArgument,
             "weight decay %g outside [0, 10)", o.weight_decay);
  TLV_ENSURE(o.adam_beta1 >= 0 && o.adam_beta1 < 1 && o.adam_beta2 >= 0 && o.adam_beta2 < 1,
             ErrorCode::kInvalidArgument, "AdamW betas (%g, %g) outside [0, 1)", o.adam_beta1,
             o.adam_beta2);
  TLV_ENSURE(o.adam_eps > 0 && o.adam_eps < 1, ErrorCode::kInvalidArgument,
             "AdamW eps %g outside (0, 1)", o.adam_eps);
  TLV_ENSURE(o.init_temperature > 0 && o.init_temperature <= 1, ErrorCode::kInvalidArgument,
             "initial temperature %g outside (0, 1]", o.init_temperature);
  TLV_ENSURE(o.max_logit_scale >= 1 && o.max_logit_scale >= 1.0 / o.init_temperature,
             ErrorCode::kInvalidArgument,
             "maximum logit scale %g must be >= 1 and >= 1 / initial temperature (%g)",
             o.max_logit_scale, 1.0 / o.init_temperature);
  TLV_ENSURE(o.batch >= 2 && o.batch <= kMaxBatch, ErrorCode::kInvalidArgument,
             "batch %d outside 2..%d (InfoNCE needs at least two pairs)", o.batch, kMaxBatch);
  TLV_ENSURE(o.epochs >= 1 && o.epochs <= 10000, ErrorCode::kInvalidArgument,
             "epochs %d outside 1..10000", o.epochs);
  TLV_ENSURE(o.max_steps >= 0, ErrorCode::kInvalidArgument, "max steps %lld < 0",
             static_cast<long long>(o.max_steps));
  TLV_ENSURE(o.threads >= 1 && o.threads <= kMaxThreads, ErrorCode::kInvalidArgument,
             "threads %d outside 1..%d", o.threads, kMaxThreads);
  TLV_ENSURE(o.checkpoint_every >= 1, ErrorCode::kInvalidArgument,
             "checkpoint interval %lld < 1 step", static_cast<long long>(o.checkpoint_every));
  TLV_ENSURE(o.max_samples >= 0, ErrorCode::kInvalidArgument, "max samples %lld < 0",
             static_cast<long long>(o.max_samples));
  TLV_ENSURE(o.test_fraction >= 0 && o.test_fraction < 1, ErrorCode::kInvalidArgument,
             "test fraction %g outside [0, 1)", o.test_fraction);
  const TeacherOptions& t = o.teacher;
  if (t.torchscript.empty()) {
    TLV_TRY(make_arch(t.builtin_arch, o.input_height, o.input_width, o.text.dim).status());
    TLV_ENSURE(t.epochs >= 1 && t.epochs <= 1000, ErrorCode::kInvalidArgument,
               "teacher epochs %d outside 1..1000", t.epochs);
    TLV_ENSURE(t.lr > 0 && t.lr < 1, ErrorCode::kInvalidArgument,
               "teacher learning rate %g outside (0, 1)", t.lr);
  } else {
    TLV_ENSURE(t.input_height >= kMinInputSide && t.input_height <= kMaxInputSide &&
                   t.input_width >= kMinInputSide && t.input_width <= kMaxInputSide,
               ErrorCode::kInvalidArgument, "teacher input %dx%d: sides must be in %d..%d",
               t.input_height, t.input_width, kMinInputSide, kMaxInputSide);
    TLV_ENSURE(t.mean.size() == 3 && t.std.size() == 3, ErrorCode::kInvalidArgument,
               "teacher mean/std need 3 values each (RGB), got %zu/%zu", t.mean.size(),
               t.std.size());
    for (float s : t.std) {
      TLV_ENSURE(s > 0 && std::isfinite(s), ErrorCode::kInvalidArgument,
                 "teacher std %g must be positive", static_cast<double>(s));
    }
  }
  return {};
}

nlohmann::ordered_json options_to_json(const TrainOptions& o) {
  nlohmann::ordered_json teacher;
  if (o.beta.schedule == BetaSchedule::kNone) {
    teacher = {{"kind", "none (no curriculum: beta = 0, the teacher is never used)"}};
  } else if (o.teacher.torchscript.empty()) {
    teacher = {{"kind", "builtin"},
               {"arch", o.teacher.builtin_arch},
               {"epochs", o.teacher.epochs},
               {"lr", o.teacher.lr}};
  } else {
    teacher = {{"kind", "torchscript"},
               {"file", o.teacher.torchscript},
               {"input", {o.teacher.input_height, o.teacher.input_width}},
               {"mean", o.teacher.mean},
               {"std", o.teacher.std}};
  }
  nlohmann::ordered_json view = {{"components", view_components_name(o.view.components)},
                                 {"consistency_weight", o.view.consistency_weight},
                                 {"prediction_weight", o.view.prediction_weight},
                                 {"frame", {o.view.frame_height, o.view.frame_width}}};
  // Written only when used: the records of runs without it stay byte for byte what they were.
  if (o.view.codec_pairs > 0) view["codec_pairs"] = o.view.codec_pairs;
  return {
      {"arch", o.arch},
      {"input", {o.input_height, o.input_width}},
      {"resize", resize_filter_name(o.resize)},
      {"text",
       {{"embeddings_dir", o.text.embeddings_dir}, {"dim", o.text.dim}, {"seed", o.text.seed}}},
      {"teacher", teacher},
      {"beta",
       {{"schedule", beta_schedule_name(o.beta.schedule)},
        {"beta1", o.beta.beta1},
        {"span", o.beta.span},
        {"beta_min", o.beta.beta_min}}},
      {"objective", objective_name(o.objective)},
      {"supervised_weight", o.supervised_weight},
      {"contact_weight", o.contact_weight},
      {"augment",
       {{"gain_sigma", o.augment.gain_sigma},
        {"exposure_sigma", o.augment.exposure_sigma},
        {"noise_dn", o.augment.noise_dn}}},
      {"view", view},
      {"lr", o.lr.lr},
      {"warmup_steps", o.lr.warmup_steps},
      {"min_lr", o.lr.min_lr},
      {"weight_decay", o.weight_decay},
      {"adam", {o.adam_beta1, o.adam_beta2, o.adam_eps}},
      {"init_temperature", o.init_temperature},
      {"max_logit_scale", o.max_logit_scale},
      {"batch", o.batch},
      {"epochs", o.epochs},
      {"max_steps", o.max_steps},
      {"seed", o.seed},
      {"max_samples", o.max_samples},
      {"test_fraction", o.test_fraction},
      {"checkpoint_every", o.checkpoint_every},
  };
}

Status options_from_json(const nlohmann::ordered_json& j, TrainOptions& o) {
  try {
    o.arch = j.at("arch").get<std::string>();
    o.input_height = j.at("input").at(0).get<int32_t>();
    o.input_width = j.at("input").at(1).get<int32_t>();
    o.text.embeddings_dir = j.at("text").at("embeddings_dir").get<std::string>();
    o.text.dim = j.at("text").at("dim").get<int32_t>();
    o.text.seed = j.at("text").at("seed").get<uint64_t>();
    const nlohmann::ordered_json& t = j.at("teacher");
    const std::string kind = t.at("kind").get<std::string>();
    if (kind == "builtin") {
      o.teacher.torchscript.clear();
      o.teacher.builtin_arch = t.at("arch").get<std::string>();
      o.teacher.epochs = t.at("epochs").get<int32_t>();
      o.teacher.lr = t.at("lr").get<double>();
    } else if (kind == "torchscript") {
      o.teacher.torchscript = t.at("file").get<std::string>();
      o.teacher.input_height = t.at("input").at(0).get<int32_t>();
      o.teacher.input_width = t.at("input").at(1).get<int32_t>();
      o.teacher.mean = t.at("mean").get<std::vector<float>>();
      o.teacher.std = t.at("std").get<std::vector<float>>();
    }
    TLV_ASSIGN_OR_RETURN(o.beta.schedule,
                         parse_beta_schedule(j.at("beta").at("schedule").get<std::string>()));
    o.beta.beta1 = j.at("beta").at("beta1").get<double>();
    o.beta.span = j.at("beta").at("span").get<double>();
    o.beta.beta_min = j.at("beta").at("beta_min").get<double>();
    // Settings added later (issue 16): checkpoints written before them trained TLV-Link alone,
    // without augmentation.
    TLV_ASSIGN_OR_RETURN(o.objective, parse_objective(j.value("objective", "tlv-link")));
    o.supervised_weight = j.value("supervised_weight", 1.0);
    o.contact_weight = j.value("contact_weight", 0.0);  // added later still: none before
    if (j.contains("augment")) {
      o.augment.gain_sigma = j.at("augment").at("gain_sigma").get<double>();
      o.augment.exposure_sigma = j.at("augment").at("exposure_sigma").get<double>();
      o.augment.noise_dn = j.at("augment").at("noise_dn").get<double>();
    } else {
      o.augment = {};
    }
    // Added with issue 29: checkpoints before it resized bilinearly and made no views.
    const std::string resize = j.value("resize", "bilinear");
    o.resize = resize == "area" ? ResizeFilter::kArea : ResizeFilter::kBilinear;
    if (j.contains("view")) {
      TLV_ASSIGN_OR_RETURN(o.view.components,
                           parse_view_components(j.at("view").at("components").get<std::string>()));
      o.view.consistency_weight = j.at("view").at("consistency_weight").get<double>();
      o.view.prediction_weight = j.at("view").value("prediction_weight", 0.0);
      o.view.codec_pairs = j.at("view").value("codec_pairs", 0.0);
      o.view.frame_height = j.at("view").at("frame").at(0).get<int32_t>();
      o.view.frame_width = j.at("view").at("frame").at(1).get<int32_t>();
    } else {
      o.view = {};
    }
    o.lr.lr = j.at("lr").get<double>();
    o.lr.warmup_steps = j.at("warmup_steps").get<int64_t>();
    o.lr.min_lr = j.at("min_lr").get<double>();
    o.weight_decay = j.at("weight_decay").get<double>();
    o.adam_beta1 = j.at("adam").at(0).get<double>();
    o.adam_beta2 = j.at("adam").at(1).get<double>();
    o.adam_eps = j.at("adam").at(2).get<double>();
    o.init_temperature = j.at("init_temperature").get<double>();
    o.max_logit_scale = j.at("max_logit_scale").get<double>();
    o.batch = j.at("batch").get<int32_t>();
    o.epochs = j.at("epochs").get<int32_t>();
    o.max_steps = j.at("max_steps").get<int64_t>();
    o.seed = j.at("seed").get<uint64_t>();
    o.max_samples = j.at("max_samples").get<int64_t>();
    o.test_fraction = j.at("test_fraction").get<double>();
    o.checkpoint_every = j.at("checkpoint_every").get<int64_t>();
  } catch (const nlohmann::json::exception& e) {
    return Error::make(ErrorCode::kFormat, "checkpoint settings: %s", e.what());
  }
  return {};
}

std::vector<int64_t> epoch_order(int64_t n, uint64_t seed, int64_t epoch) {
  std::vector<int64_t> order(static_cast<size_t>(std::max<int64_t>(n, 0)));
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int64_t>(i);
  uint64_t state = seed ^ (static_cast<uint64_t>(epoch + 1) * 0xd1b54a32d192ed03ull);
  auto next = [&state] {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  for (size_t i = order.size(); i > 1; --i) {
    const size_t j = static_cast<size_t>(next() % i);  // modulo bias < n / 2^64: negligible
    std::swap(order[i - 1], order[j]);
  }
  return order;
}

}  // namespace tlvlink::trainer
