// Built-in teacher pre-training and TorchScript teachers.

#include "teacher.h"

#include <torch/optim/adamw.h>
#include <torch/script.h>

#include <chrono>
#include <cmath>

#include "options_json.h"
#include "train_monitor.h"

namespace tlvlink::trainer {
namespace {

// Teacher shuffles use their own stream so the student's data order does not depend on them.
constexpr uint64_t kTeacherSeedStream = 0x7ea7c4e7ull;

}  // namespace

Result<TeacherOutput> pretrain_builtin_teacher(const DataCache& cache, const torch::Tensor& text,
                                               const TrainOptions& o, std::FILE* log) {
  const auto start = std::chrono::steady_clock::now();
  TLV_ASSIGN_OR_RETURN(ArchSpec arch,
                       make_arch(o.teacher.builtin_arch, cache.vision_height, cache.vision_width,
                                 static_cast<int32_t>(text.size(1))));
  const int64_t n = cache.size();
  const int64_t batch = std::min<int64_t>(o.batch, n);
  TLV_ENSURE(batch >= 2, ErrorCode::kInvalidArgument,
             "the teacher needs at least 2 training samples, the set has %lld",
             static_cast<long long>(n));
  const int64_t steps_per_epoch = n / batch;
  const int64_t total = steps_per_epoch * o.teacher.epochs;
  std::vector<float> mean, std;
  channel_stats(cache.vision, mean, std);

  EncoderNet net(arch);
  torch::Tensor logit_scale =
      torch::full({}, std::log(1.0 / o.init_temperature), torch::kFloat32).set_requires_grad(true);
  std::vector<torch::Tensor> decay, no_decay{logit_scale};
  for (const auto& p : net->named_parameters()) {
    (decays(p.key(), p.value()) ? decay : no_decay).push_back(p.value());
  }
  auto options =
      torch::optim::AdamWOptions(o.teacher.lr).betas({o.adam_beta1, o.adam_beta2}).eps(o.adam_eps);
  std::vector<torch::optim::OptimizerParamGroup> groups;
  groups.emplace_back(decay, std::make_unique<torch::optim::AdamWOptions>(
                                 torch::optim::AdamWOptions(options).weight_decay(o.weight_decay)));
  groups.emplace_back(no_decay, std::make_unique<torch::optim::AdamWOptions>(
                                    torch::optim::AdamWOptions(options).weight_decay(0.0)));
  torch::optim::AdamW optimizer(std::move(groups), options);
  const LrOptions lr{o.teacher.lr, std::min<int64_t>(o.lr.warmup_steps, total / 10), 0.0};
  const double max_log_scale = std::log(o.max_logit_scale);

  TrainMonitor monitor("teacher", 0, total, batch, log);
  net->train();
  std::vector<double> epoch_losses;
  double last_loss = 0;
  for (int64_t epoch = 0; epoch < o.teacher.epochs; ++epoch) {
    const std::vector<int64_t> order = epoch_order(n, o.seed ^ kTeacherSeedStream, epoch);
    double sum = 0;
    for (int64_t s = 0; s < steps_per_epoch; ++s) {
      const int64_t step = epoch * steps_per_epoch + s;
      const std::vector<int64_t> idx(order.begin() + s * batch, order.begin() + (s + 1) * batch);
      const double rate = lr_at(lr, step, total);
      for (auto& g : optimizer.param_groups()) {
        static_cast<torch::optim::AdamWOptions&>(g.options()).lr(rate);
      }
      const torch::Tensor x =
          image_batch(cache.vision, cache.vision_height, cache.vision_width, idx, mean, std);
      const torch::Tensor y = text.index_select(0, torch::tensor(idx, torch::kLong));
      torch::Tensor loss = clip_loss(net->forward(x), y, logit_scale.exp());
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      {
        torch::NoGradGuard no_grad;
        logit_scale.clamp_(0.0, max_log_scale);
      }
      last_loss = loss.item<double>();
      TLV_ENSURE(std::isfinite(last_loss), ErrorCode::kInvalidState,
                 "teacher loss became %g at step %lld (learning rate %g too high?)", last_loss,
                 static_cast<long long>(step), rate);
      sum += last_loss;
      monitor.step(step, epoch, last_loss, 0.0, std::exp(-logit_scale.item<double>()), rate);
    }
    epoch_losses.push_back(sum / static_cast<double>(steps_per_epoch));
    monitor.epoch_end(epoch, o.teacher.epochs, epoch_losses.back());
  }
  monitor.finish();

  TeacherOutput out;
  out.embeddings =
      embed_all(net, cache.vision, cache.vision_height, cache.vision_width, n, mean, std);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.provenance = {{"kind", "builtin"},
                    {"arch", describe_arch(arch)},
                    {"epochs", o.teacher.epochs},
                    {"lr", o.teacher.lr},
                    {"epoch_losses", epoch_losses},
                    {"final_loss", last_loss},
                    {"final_temperature", std::exp(-logit_scale.item<double>())},
                    {"vision_mean", mean},
                    {"vision_std", std},
                    {"samples_per_s", monitor.samples_per_s()},
                    {"seconds", seconds}};
  return out;
}

Result<TeacherOutput> run_torchscript_teacher(const DataCache& cache, const TrainOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::string& path = o.teacher.torchscript;
  torch::jit::script::Module module;
  try {
    module = torch::jit::load(path);
  } catch (const std::exception& e) {
    return Error::make(ErrorCode::kFormat, "teacher %s: not a loadable TorchScript module: %s",
                       path.c_str(), first_line(e.what()).c_str());
  }
  module.eval();
  torch::NoGradGuard no_grad;
  constexpr int64_t kChunk = 64;
  const int64_t n = cache.size();
  std::vector<torch::Tensor> parts;
  for (int64_t begin = 0; begin < n; begin += kChunk) {
    std::vector<int64_t> idx;
    for (int64_t i = begin; i < std::min(n, begin + kChunk); ++i) idx.push_back(i);
    const torch::Tensor x = image_batch(cache.vision, cache.vision_height, cache.vision_width, idx,
                                        o.teacher.mean, o.teacher.std);
    torch::Tensor y;
    try {
      const c10::IValue r = module.forward({x});
      TLV_ENSURE(r.isTensor(), ErrorCode::kFormat,
                 "teacher %s: forward() returned %s, expected one tensor [N, D]", path.c_str(),
                 r.tagKind().c_str());
      y = r.toTensor().to(torch::kFloat32);
    } catch (const std::exception& e) {
      return Error::make(ErrorCode::kFormat, "teacher %s failed on input [%lld, 3, %d, %d]: %s",
                         path.c_str(), static_cast<long long>(idx.size()), cache.vision_height,
                         cache.vision_width, first_line(e.what()).c_str());
    }
    TLV_ENSURE(y.dim() == 2 && y.size(0) == static_cast<int64_t>(idx.size()) && y.size(1) >= 1,
               ErrorCode::kFormat, "teacher %s returned shape %s, expected [%zu, D]", path.c_str(),
               c10::str(y.sizes()).c_str(), idx.size());
    TLV_ENSURE(torch::isfinite(y).all().item<bool>(), ErrorCode::kNonFiniteValue,
               "teacher %s returned NaN/Inf for samples %lld..%lld", path.c_str(),
               static_cast<long long>(begin), static_cast<long long>(begin + y.size(0) - 1));
    parts.push_back(y.contiguous());
  }
  TeacherOutput out;
  out.embeddings = torch::cat(parts, 0);
  out.provenance = {
      {"kind", "torchscript"},
      {"file", path},
      {"input", {o.teacher.input_height, o.teacher.input_width}},
      {"mean", o.teacher.mean},
      {"std", o.teacher.std},
      {"output_dim", out.embeddings.size(1)},
      {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  return out;
}

}  // namespace tlvlink::trainer
