// tlvlink::trainer::train — TLV-Link curriculum training of the edge student.

#include <torch/nn/functional/distance.h>
#include <torch/optim/adamw.h>
#include <torch/utils.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>

#include "augment.h"
#include "checkpoint.h"
#include "data_cache.h"
#include "options_json.h"
#include "teacher.h"
#include "tlvlink/log.h"
#include "tlvlink/text/text_encoder.h"
#include "train_monitor.h"
#include "view_batches.h"

namespace tlvlink::trainer {
namespace {

TLV_LOG_CATEGORY(kLogTrain, "train");

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

Result<std::unique_ptr<text::TextEncoder>> open_text_encoder(const TextOptions& t) {
  if (!t.embeddings_dir.empty()) return text::open_precomputed_text_embeddings(t.embeddings_dir);
  return text::make_hashing_text_encoder({.dim = t.dim, .seed = t.seed});
}

// y_i = normalise(sentence_i) + normalise(phrases_i), one row per sample.
Result<torch::Tensor> text_features(text::TextEncoder& encoder, const DataCache& cache) {
  const int64_t n = cache.size();
  const int64_t d = encoder.dim();
  torch::Tensor y = torch::empty({n, d}, torch::kFloat32);
  float* dst = y.data_ptr<float>();
  for (int64_t i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    auto f = text::text_feature(encoder, cache.keys[k], cache.sentences[k], cache.phrase_descs[k]);
    if (!f.ok()) return f.error().with_context("text of sample '%s'", cache.keys[k].c_str());
    TLV_ENSURE(static_cast<int64_t>(f->size()) == d, ErrorCode::kInvalidState,
               "text feature of '%s' has %zu values, encoder dim %lld", cache.keys[k].c_str(),
               f->size(), static_cast<long long>(d));
    std::copy(f->begin(), f->end(), dst + i * d);
  }
  return y;
}

// Weight decay on conv/FC weights (and the projection's weight); none on BN, biases and the
// temperature (CLIP's rule). Group order is fixed, so a saved state restores into it.
std::unique_ptr<torch::optim::AdamW> make_optimizer(TrainState& s, const TrainOptions& o) {
  std::vector<torch::Tensor> decay, no_decay{s.logit_scale};
  for (const auto& p : s.student->named_parameters()) {
    (decays(p.key(), p.value()) ? decay : no_decay).push_back(p.value());
  }
  if (s.projection) {
    decay.push_back(s.projection->weight);
    no_decay.push_back(s.projection->bias);
  }
  if (s.heads) {
    for (const auto& p : s.heads->named_parameters()) {
      (p.value().dim() >= 2 ? decay : no_decay).push_back(p.value());
    }
  }
  auto base =
      torch::optim::AdamWOptions(o.lr.lr).betas({o.adam_beta1, o.adam_beta2}).eps(o.adam_eps);
  std::vector<torch::optim::OptimizerParamGroup> groups;
  groups.emplace_back(decay, std::make_unique<torch::optim::AdamWOptions>(
                                 torch::optim::AdamWOptions(base).weight_decay(o.weight_decay)));
  groups.emplace_back(no_decay, std::make_unique<torch::optim::AdamWOptions>(
                                    torch::optim::AdamWOptions(base).weight_decay(0.0)));
  return std::make_unique<torch::optim::AdamW>(std::move(groups), base);
}

Result<std::FILE*> open_log(const std::string& path, bool append) {
  std::FILE* f = std::fopen(path.c_str(), append ? "a" : "w");
  TLV_ENSURE(f != nullptr, ErrorCode::kIo, "cannot open training log %s", path.c_str());
  return f;
}

struct LogCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

Status make_dirs(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot create directory %s: %s", dir.c_str(),
             ec.message().c_str());
  return {};
}

Status make_parent_dirs(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? Status() : make_dirs(parent.string());
}

std::string step_checkpoint_path(const std::string& dir, int64_t step) {
  char name[40];
  std::snprintf(name, sizeof(name), "/step_%07lld.ckpt", static_cast<long long>(step));
  return dir + name;
}

// The batch of touch frames `idx` from model-size frames `pixels` (the cache, or the views of
// a step), augmented per sample when the photometric options ask for it (the augmented copies
// go through `scratch`, so the cache keeps the original pixels).
torch::Tensor touch_batch(const std::vector<uint8_t>& pixels, int32_t height, int32_t width,
                          const std::vector<int64_t>& idx, const std::vector<int64_t>& keys,
                          const std::vector<float>& mean, const std::vector<float>& std,
                          const TrainOptions& o, int64_t step, std::vector<uint8_t>& scratch) {
  if (!o.augment.enabled()) return image_batch(pixels, height, width, idx, mean, std);
  const size_t stride = static_cast<size_t>(height) * static_cast<size_t>(width) * 3;
  scratch.resize(idx.size() * stride);
  std::vector<int64_t> rows(idx.size());
  for (size_t i = 0; i < idx.size(); ++i) {
    augment_frame(pixels.data() + static_cast<size_t>(idx[i]) * stride, scratch.data() + i * stride,
                  height, width, o.augment, augment_seed(o.seed, step, keys[i]));
    rows[i] = static_cast<int64_t>(i);
  }
  return image_batch(scratch, height, width, rows, mean, std);
}

}  // namespace

Result<TrainSummary> train(const TrainOptions& requested) {
  const auto t0 = Clock::now();
  TrainOptions o = requested;
  TrainSummary summary;

  // A resumed run takes every result-determining setting from its checkpoint.
  std::optional<TrainState> resumed;
  if (!o.resume.empty()) {
    TLV_ASSIGN_OR_RETURN(TrainState s, load_checkpoint(o.resume));
    try {
      TLV_TRY(options_from_json(s.meta.at("settings"), o));
    } catch (const nlohmann::json::exception& e) {
      return Error::make(ErrorCode::kFormat, "%s: no settings in the checkpoint: %s",
                         o.resume.c_str(), e.what());
    }
    resumed = std::move(s);
  }
  TLV_TRY(validate(o));
  // Output places first, so a typo fails before minutes of loading and pre-training.
  TLV_TRY(make_parent_dirs(o.output));
  if (!o.checkpoint_dir.empty()) TLV_TRY(make_dirs(o.checkpoint_dir));
  summary.log_path = o.log_path.empty() ? o.output + ".log.jsonl" : o.log_path;
  TLV_TRY(make_parent_dirs(summary.log_path));
  TLV_ASSIGN_OR_RETURN(std::FILE * log_file, open_log(summary.log_path, resumed.has_value()));
  const std::unique_ptr<std::FILE, LogCloser> log(log_file);
  torch::set_num_threads(o.threads);
  torch::manual_seed(o.seed);

  TLV_ASSIGN_OR_RETURN(std::unique_ptr<text::TextEncoder> encoder, open_text_encoder(o.text));
  o.text.dim = encoder->dim();
  TLV_ASSIGN_OR_RETURN(const ArchSpec arch,
                       make_arch(o.arch, o.input_height, o.input_width, o.text.dim));
  summary.arch_description = describe_arch(arch);
  TLV_LOG(kLogTrain, kInfo, "student: %s", summary.arch_description.c_str());

  const bool curriculum = o.beta.schedule != BetaSchedule::kNone;
  const bool text_loss = o.objective != Objective::kSupervised;
  const bool supervised = o.objective != Objective::kTlvLink;
  const bool torchscript_teacher = curriculum && !o.teacher.torchscript.empty();
  CacheOptions co;
  co.dir = o.data_dir;
  co.split = SplitChoice::kTrain;
  // With the sensor-view augmentation the cache keeps frames at the sensor's size: the views
  // are made there, then resized like the board resizes them.
  co.touch_height = o.view.enabled() ? o.view.frame_height : o.input_height;
  co.touch_width = o.view.enabled() ? o.view.frame_width : o.input_width;
  co.resize = o.resize;
  co.keep_turned = o.view.enabled();
  co.load_vision = curriculum && !resumed;  // a resumed run has the teacher's embeddings
  co.vision_height = torchscript_teacher ? o.teacher.input_height : o.input_height;
  co.vision_width = torchscript_teacher ? o.teacher.input_width : o.input_width;
  co.max_samples = o.max_samples;
  co.max_cache_bytes = o.max_cache_bytes;
  co.test_fraction = o.test_fraction;
  co.threads = static_cast<unsigned>(std::max(2, o.threads));  // decoding parallelises freely
  TLV_ASSIGN_OR_RETURN(DataCache cache, load_cache(co));
  const int64_t n = cache.size();
  summary.train_samples = n;
  TLV_LOG(kLogTrain, kInfo, "data: %lld training samples from %s (%s; split from %s)",
          static_cast<long long>(n), o.data_dir.c_str(), cache.load_summary.c_str(),
          cache.split_source.c_str());
  TLV_ENSURE(n >= o.batch, ErrorCode::kInvalidArgument,
             "%s: %lld training samples, fewer than one batch of %d; lower --batch",
             o.data_dir.c_str(), static_cast<long long>(n), o.batch);
  if (resumed) {
    const std::string fp = std::to_string(cache.fingerprint());
    TLV_ENSURE(resumed->meta.value("data_fingerprint", "") == fp, ErrorCode::kInvalidArgument,
               "%s: the training samples differ from those the checkpoint %s was trained on "
               "(%lld samples now)",
               o.data_dir.c_str(), o.resume.c_str(), static_cast<long long>(n));
  }
  if (supervised) {
    const bool labelled =
        std::any_of(cache.material.begin(), cache.material.end(), [](int32_t m) { return m >= 0; });
    TLV_ENSURE(labelled, ErrorCode::kInvalidArgument,
               "%s: objective %s needs labels, and no training sample has any (only a simulated "
               "set's sidecar records material, hard/soft and rough/smooth)",
               o.data_dir.c_str(), objective_name(o.objective));
    if (o.contact_weight > 0) {
      const auto with_contact = std::count_if(cache.log_force.begin(), cache.log_force.end(),
                                              [](float f) { return std::isfinite(f); });
      TLV_ENSURE(with_contact > 0, ErrorCode::kInvalidArgument,
                 "%s: the contact regression (--contact-weight %g) needs the frames' force and "
                 "friction, and no training sample's sidecar records a contact; pass "
                 "--contact-weight 0",
                 o.data_dir.c_str(), o.contact_weight);
      TLV_LOG(kLogTrain, kInfo,
              "contact regression: %lld of %lld samples record force and friction",
              static_cast<long long>(with_contact), static_cast<long long>(n));
    }
  }
  TLV_ASSIGN_OR_RETURN(const torch::Tensor text, text_features(*encoder, cache));

  std::vector<float> mean, std;
  channel_stats(cache.touch, mean, std);
  summary.load_seconds = seconds_since(t0);

  // The teacher: frozen embeddings of every training sample.
  TrainState state;
  nlohmann::ordered_json teacher_provenance = {{"kind", "none"}};
  int64_t teacher_dim = 0;
  if (resumed) {
    state = std::move(*resumed);
    resumed.reset();
    if (state.meta.contains("teacher")) teacher_provenance = state.meta.at("teacher");
    teacher_dim = state.meta.value("teacher_dim", int64_t{0});
  } else {
    state.student = EncoderNet(arch);
    state.logit_scale = torch::full({}, std::log(1.0 / o.init_temperature), torch::kFloat32);
    if (supervised) state.heads = SupervisedHeads(o.text.dim, o.contact_weight > 0);
    if (curriculum) {
      const auto tt = Clock::now();
      auto teacher = torchscript_teacher ? run_torchscript_teacher(cache, o)
                                         : pretrain_builtin_teacher(cache, text, o, log.get());
      if (!teacher.ok()) return teacher.error();
      state.teacher_embeddings = teacher->embeddings;
      teacher_provenance = teacher->provenance;
      teacher_dim = state.teacher_embeddings.size(1);
      if (teacher_dim != o.text.dim) {
        state.projection = torch::nn::Linear(teacher_dim, o.text.dim);
        TLV_LOG(kLogTrain, kInfo,
                "teacher output dim %lld != text dim %d: learning a linear projection",
                static_cast<long long>(teacher_dim), o.text.dim);
      }
      summary.teacher_seconds = seconds_since(tt);
    }
  }
  state.logit_scale.set_requires_grad(true);
  cache.vision = {};  // the images of the teacher are no longer needed
  if (curriculum) {
    TLV_ENSURE(state.teacher_embeddings.defined() && state.teacher_embeddings.size(0) == n,
               ErrorCode::kInvalidState, "teacher embeddings missing or sized for another set");
  }

  const int64_t steps_per_epoch = n / o.batch;
  const int64_t total = o.max_steps > 0 ? o.max_steps : steps_per_epoch * o.epochs;
  const int64_t epochs = (total + steps_per_epoch - 1) / steps_per_epoch;
  summary.steps_per_epoch = steps_per_epoch;
  summary.steps = total;

  std::unique_ptr<torch::optim::AdamW> optimizer = make_optimizer(state, o);
  int64_t start = 0;
  std::vector<double> epoch_losses;
  double epoch_sum = 0;
  int64_t epoch_count = 0;
  double last_loss = 0;
  if (!o.resume.empty()) {
    TLV_TRY(load_optimizer_state(o.resume, *optimizer));
    try {
      start = state.meta.at("step").get<int64_t>();
      epoch_losses = state.meta.at("epoch_losses").get<std::vector<double>>();
      epoch_sum = state.meta.at("epoch_loss_sum").get<double>();
      epoch_count = state.meta.at("epoch_loss_count").get<int64_t>();
      last_loss = state.meta.at("last_loss").get<double>();
      mean = state.meta.at("input").at("mean").get<std::vector<float>>();
      std = state.meta.at("input").at("std").get<std::vector<float>>();
    } catch (const nlohmann::json::exception& e) {
      return Error::make(ErrorCode::kFormat, "%s: progress record: %s", o.resume.c_str(), e.what());
    }
    TLV_LOG(kLogTrain, kInfo, "resuming %s at step %lld of %lld", o.resume.c_str(),
            static_cast<long long>(start), static_cast<long long>(total));
  }
  summary.start_step = start;

  nlohmann::ordered_json settings = options_to_json(o);
  auto fill_meta = [&](int64_t next_step) {
    nlohmann::ordered_json m;
    m["format"] = kCheckpointFormat;
    m["version"] = kCheckpointVersion;
    m["settings"] = settings;
    m["arch"] = {{"name", arch.name},
                 {"input", {arch.input_height, arch.input_width}},
                 {"embedding_dim", arch.embedding_dim},
                 {"description", describe_arch(arch)}};
    m["input"] = {{"height", o.input_height},
                  {"width", o.input_width},
                  {"channel_order", "RGB"},
                  {"resize", resize_filter_name(o.resize)},
                  {"mean", mean},
                  {"std", std}};
    m["text_encoder"] = {{"description", encoder->description()},
                         {"embeddings_dir", o.text.embeddings_dir},
                         {"dim", o.text.dim},
                         {"seed", o.text.seed}};
    m["teacher"] = teacher_provenance;
    m["teacher_dim"] = teacher_dim;
    m["dataset"] = {{"dir", o.data_dir},
                    {"train_samples", n},
                    {"sensors", cache.sensors},
                    {"split_source", cache.split_source},
                    {"load_summary", cache.load_summary}};
    m["data_fingerprint"] = std::to_string(cache.fingerprint());
    m["step"] = next_step;
    m["total_steps"] = total;
    m["steps_per_epoch"] = steps_per_epoch;
    m["epoch_losses"] = epoch_losses;
    m["epoch_loss_sum"] = epoch_sum;
    m["epoch_loss_count"] = epoch_count;
    m["last_loss"] = last_loss;
    m["temperature"] = std::exp(-state.logit_scale.item<double>());
    m["written_utc"] = utc_now();
    state.meta = m;
  };

  namespace F = torch::nn::functional;
  const double max_log_scale = std::log(o.max_logit_scale);
  const torch::Tensor teacher_unit =
      curriculum && !state.projection
          ? F::normalize(state.teacher_embeddings, F::NormalizeFuncOptions().dim(1))
          : torch::Tensor();
  TrainMonitor monitor("student", start, total, o.batch, log.get());
  state.student->train();
  if (state.heads) state.heads->train();
  TLV_ENSURE(supervised == static_cast<bool>(state.heads), ErrorCode::kInvalidState,
             "checkpoint and objective disagree about the supervised heads");
  std::vector<uint8_t> augment_scratch;
  std::vector<int64_t> order;
  int64_t order_epoch = -1;
  // The samples of `step` (epoch orders depend only on seed and epoch).
  const auto samples_of = [&](int64_t step) {
    const int64_t epoch = step / steps_per_epoch;
    const int64_t pos = step % steps_per_epoch;
    if (epoch != order_epoch) {
      order = epoch_order(n, o.seed, epoch);
      order_epoch = epoch;
    }
    return std::vector<int64_t>(order.begin() + pos * o.batch, order.begin() + (pos + 1) * o.batch);
  };
  std::unique_ptr<ViewBatches> views;
  if (o.view.enabled()) {
    InputSpec model_input;
    model_input.height = o.input_height;
    model_input.width = o.input_width;
    model_input.resize_filter = o.resize;
    model_input.mean = mean;
    model_input.std = std;
    TLV_ASSIGN_OR_RETURN(views, ViewBatches::create(cache, o, model_input));
    if (start < total) views->request(start, samples_of(start));
  }
  const int32_t view_count = views ? views->views() : 1;
  for (int64_t step = start; step < total; ++step) {
    const int64_t epoch = step / steps_per_epoch;
    const int64_t pos = step % steps_per_epoch;
    const std::vector<int64_t> idx = samples_of(step);
    const torch::Tensor rows = torch::tensor(idx, torch::kLong);
    const double rate = lr_at(o.lr, step, total);
    for (auto& g : optimizer->param_groups()) {
      static_cast<torch::optim::AdamWOptions&>(g.options()).lr(rate);
    }
    const double beta = beta_at(o.beta, step, total);
    torch::Tensor x;
    if (views) {
      TLV_ASSIGN_OR_RETURN(const std::vector<uint8_t>* made, views->take());
      std::vector<int64_t> slots(static_cast<size_t>(view_count) * idx.size());
      std::vector<int64_t> keys(slots.size());
      for (size_t i = 0; i < slots.size(); ++i) {
        slots[i] = static_cast<int64_t>(i);
        keys[i] = idx[i % idx.size()];
      }
      x = touch_batch(*made, o.input_height, o.input_width, slots, keys, mean, std, o, step,
                      augment_scratch);
      if (step + 1 < total) views->request(step + 1, samples_of(step + 1));
    } else {
      x = touch_batch(cache.touch, cache.height, cache.width, idx, idx, mean, std, o, step,
                      augment_scratch);
    }
    // One forward pass over every view; the losses average over the views.
    const torch::Tensor all = state.student->forward(x);
    const std::vector<torch::Tensor> per_view = all.chunk(view_count, 0);
    torch::Tensor loss = torch::zeros({});
    for (const torch::Tensor& touch : per_view) {
      torch::Tensor mixed = touch;
      if (text_loss && curriculum && beta > 0) {
        torch::Tensor vision =
            state.projection
                ? F::normalize(
                      state.projection->forward(state.teacher_embeddings.index_select(0, rows)),
                      F::NormalizeFuncOptions().dim(1))
                : teacher_unit.index_select(0, rows);
        mixed =
            beta * vision + (1.0 - beta) * F::normalize(touch, F::NormalizeFuncOptions().dim(1));
      }
      torch::Tensor view_loss = torch::zeros({});
      if (text_loss)
        view_loss = clip_loss(mixed, text.index_select(0, rows), state.logit_scale.exp());
      if (supervised) {
        const double w = text_loss ? o.supervised_weight : 1.0;
        view_loss = view_loss + w * state.heads->loss(touch, label_batch(cache.material, idx),
                                                      label_batch(cache.hard, idx),
                                                      label_batch(cache.rough, idx));
        if (state.heads->has_contact()) {
          view_loss =
              view_loss + w * o.contact_weight *
                              state.heads->contact_loss(touch, target_batch(cache.log_force, idx),
                                                        target_batch(cache.friction, idx));
        }
      }
      loss = loss + view_loss / static_cast<double>(view_count);
    }
    if (view_count == 2) {
      // Two views of one touch should embed alike: the codec, optics and mounting are not touch.
      const torch::Tensor agree =
          F::cosine_similarity(per_view[0], per_view[1], F::CosineSimilarityFuncOptions().dim(1));
      loss = loss + o.view.consistency_weight * (1.0 - agree).mean();
      if (o.view.prediction_weight > 0 && supervised) {
        loss =
            loss + o.view.prediction_weight * state.heads->agreement_loss(per_view[0], per_view[1]);
      }
    }
    optimizer->zero_grad();
    loss.backward();
    optimizer->step();
    {
      torch::NoGradGuard no_grad;
      state.logit_scale.clamp_(0.0, max_log_scale);
    }
    last_loss = loss.item<double>();
    TLV_ENSURE(std::isfinite(last_loss), ErrorCode::kInvalidState,
               "student loss became %g at step %lld (learning rate %g too high?)", last_loss,
               static_cast<long long>(step), rate);
    epoch_sum += last_loss;
    ++epoch_count;
    monitor.step(step, epoch, last_loss, beta, std::exp(-state.logit_scale.item<double>()), rate);
    if (pos == steps_per_epoch - 1 || step == total - 1) {
      epoch_losses.push_back(epoch_sum / static_cast<double>(epoch_count));
      monitor.epoch_end(epoch, epochs, epoch_losses.back());
      epoch_sum = 0;
      epoch_count = 0;
    }
    if (!o.checkpoint_dir.empty() && (step + 1) % o.checkpoint_every == 0 && step + 1 < total) {
      fill_meta(step + 1);
      TLV_TRY(save_checkpoint(step_checkpoint_path(o.checkpoint_dir, step + 1), state,
                              optimizer.get()));
    }
  }
  monitor.finish();
  summary.student_seconds = monitor.elapsed_s();
  summary.student_samples_per_s = monitor.samples_per_s();
  summary.final_loss = last_loss;
  summary.first_epoch_loss = epoch_losses.empty() ? 0 : epoch_losses.front();
  summary.last_epoch_loss = epoch_losses.empty() ? 0 : epoch_losses.back();

  fill_meta(total);
  state.meta["summary"] = {{"student_samples_per_s", summary.student_samples_per_s},
                           {"load_seconds", summary.load_seconds},
                           {"teacher_seconds", summary.teacher_seconds},
                           {"student_seconds", summary.student_seconds},
                           {"threads", o.threads}};
  TLV_TRY(save_checkpoint(o.output, state, optimizer.get()));
  if (!o.checkpoint_dir.empty()) {
    TLV_TRY(save_checkpoint(step_checkpoint_path(o.checkpoint_dir, total), state, optimizer.get()));
  }
  summary.checkpoint = o.output;
  return summary;
}

}  // namespace tlvlink::trainer
