// Linear head vs an encoder adapted on the user's frames, on the same grouped folds (adapt.h).

#include "tlvlink/trainer/adapt.h"

#include <torch/nn/functional/loss.h>
#include <torch/optim/adamw.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>

#include "checkpoint.h"
#include "net.h"
#include "tlvlink/eval/grouped_cv.h"
#include "tlvlink/eval/user_head.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::trainer {
namespace {

constexpr double kMinEncoderCosine = 0.999;

// Every frame through the sensor's view and the model's own preprocessing: [n, 3, H, W].
Result<torch::Tensor> model_inputs(const Model& model, const eval::LabelledFrames& frames,
                                   const std::string& sensor) {
  const InputSpec& spec = model.metadata().input;
  const int64_t per_frame = static_cast<int64_t>(spec.height) * spec.width * 3;
  torch::Tensor x = torch::empty(
      {static_cast<int64_t>(frames.frames.size()), spec.height, spec.width, 3}, torch::kFloat32);
  float* dst = x.data_ptr<float>();
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    const eval::LabelledFrame& lf = frames.frames[i];
    TLV_ENSURE(lf.record_offset == 0, ErrorCode::kInvalidArgument,
               "%s: adapt reads labelled image folders (--images), not recordings",
               lf.path.c_str());
    TLV_ASSIGN_OR_RETURN(tools::SensorFrame sf, tools::sensor_frame_from_file(lf.path, sensor));
    auto v = image::preprocess(sf.view.view(), spec);
    if (!v.ok()) return v.error().with_context("%s", lf.path.c_str());
    TLV_ENSURE(static_cast<int64_t>(v->size()) == per_frame, ErrorCode::kShapeMismatch,
               "%s: preprocessing gave %zu values, the model input needs %lld", lf.path.c_str(),
               v->size(), static_cast<long long>(per_frame));
    std::copy(v->begin(), v->end(), dst + static_cast<int64_t>(i) * per_frame);
  }
  return x.permute({0, 3, 1, 2}).contiguous();
}

torch::Tensor embed(EncoderNet& net, const torch::Tensor& x) {
  torch::NoGradGuard no_grad;
  net->eval();
  return net->forward(x);
}

double min_row_cosine(const torch::Tensor& a, const torch::Tensor& b) {
  return torch::nn::functional::cosine_similarity(
             a, b, torch::nn::functional::CosineSimilarityFuncOptions().dim(1))
      .min()
      .item<double>();
}

// Freezes the encoder but its last `layers` convs (with their BatchNorm's scale and shift) and
// the FC; BatchNorm keeps its running statistics (eval mode: a handful of frames per batch
// would make batch statistics noise). Returns the trainable parameters and their count.
std::vector<torch::Tensor> unfreeze_last(EncoderNet& net, int32_t layers, int64_t& count) {
  for (torch::Tensor& p : net->parameters()) p.set_requires_grad(false);
  std::vector<torch::Tensor> trained;
  const size_t first = net->convs.size() - static_cast<size_t>(layers);
  for (size_t i = first; i < net->convs.size(); ++i) {
    for (torch::Tensor& p : net->convs[i]->parameters()) trained.push_back(p);
    for (torch::Tensor& p : net->norms[i]->parameters()) trained.push_back(p);
  }
  for (torch::Tensor& p : net->fc->parameters()) trained.push_back(p);
  count = 0;
  for (torch::Tensor& p : trained) {
    p.set_requires_grad(true);
    count += p.numel();
  }
  return trained;
}

// One fold: the linear head fitted on the fold's training rows (grouped_cv's choice of L2)
// starts the classifier, then the unfrozen layers and the classifier train together on the
// cross-entropy (AdamW's decoupled weight decay the only regulariser: few steps at a small
// rate keep them near the start). Returns the predicted class of every row.
Result<std::vector<int32_t>> adapted_fold(const AdaptOptions& o, const torch::Tensor& x,
                                          const std::vector<int32_t>& labels,
                                          const std::vector<std::string>& groups,
                                          const std::vector<std::string>& class_names,
                                          const std::vector<int64_t>& train_rows, int32_t classes,
                                          int64_t& trained_params, double& loss_start,
                                          double& loss_end) {
  TLV_ASSIGN_OR_RETURN(TrainState state, load_checkpoint(o.checkpoint));
  EncoderNet net = state.student;
  const torch::Tensor index = torch::tensor(train_rows, torch::kInt64);
  const torch::Tensor xt = x.index_select(0, index);
  const torch::Tensor e0 = embed(net, xt).contiguous();

  std::vector<int32_t> y(train_rows.size());
  std::vector<std::string> g(train_rows.size());
  for (size_t i = 0; i < train_rows.size(); ++i) {
    y[i] = labels[static_cast<size_t>(train_rows[i])];
    g[i] = groups[static_cast<size_t>(train_rows[i])];
  }
  const auto dim = static_cast<int32_t>(e0.size(1));
  const eval::GroupedRows rows{
      std::span<const float>(e0.data_ptr<float>(), static_cast<size_t>(e0.numel())),
      dim,
      y,
      classes,
      g,
      class_names};
  eval::CvOptions cv;
  cv.folds = o.folds;
  cv.seed = o.seed;
  TLV_ASSIGN_OR_RETURN(eval::FittedProbe probe, eval::fit_grouped(rows, cv));

  torch::nn::Linear head(torch::nn::LinearOptions(dim, classes));
  {
    torch::NoGradGuard no_grad;
    head->weight.copy_(torch::tensor(probe.weight).view({classes, dim}));
    head->bias.copy_(torch::tensor(probe.bias));
  }
  std::vector<torch::Tensor> params = unfreeze_last(net, o.layers, trained_params);
  for (torch::Tensor& p : head->parameters()) params.push_back(p);
  torch::optim::AdamW opt(params, torch::optim::AdamWOptions(o.lr).weight_decay(o.weight_decay));
  const torch::Tensor target = torch::tensor(std::vector<int64_t>(y.begin(), y.end()));
  net->eval();  // BatchNorm statistics stay the trained ones (unfreeze_last)
  const auto fit_loss = [&] {
    return torch::nn::functional::cross_entropy(head->forward(net->forward(xt)), target);
  };
  for (int32_t step = 0; step < o.steps; ++step) {
    opt.zero_grad();
    torch::Tensor loss = fit_loss();
    if (step == 0) loss_start = loss.item<double>();
    loss.backward();
    opt.step();
    TLV_ENSURE(std::isfinite(loss.item<double>()), ErrorCode::kNonFiniteValue,
               "adapt: the loss became %g at step %d (lower --lr)", loss.item<double>(), step);
  }
  torch::NoGradGuard no_grad;
  loss_end = fit_loss().item<double>();
  if (o.steps == 0) loss_start = loss_end;
  const torch::Tensor predicted = head->forward(net->forward(x)).argmax(1).to(torch::kInt32);
  return std::vector<int32_t>(predicted.data_ptr<int32_t>(),
                              predicted.data_ptr<int32_t>() + predicted.numel());
}

HeadScore score(const std::vector<int32_t>& predicted, const std::vector<int32_t>& labels,
                const std::vector<std::string>& groups, int32_t classes, uint64_t seed,
                std::vector<uint8_t>& right) {
  right.resize(labels.size());
  for (size_t i = 0; i < labels.size(); ++i) right[i] = predicted[i] == labels[i] ? 1 : 0;
  const eval::ClassMetrics m = eval::class_metrics(labels, right, classes);
  const eval::Interval ci = eval::group_bootstrap_interval(right, groups, seed);
  return {m.accuracy, ci.low, ci.high, m.balanced_accuracy};
}

}  // namespace

Result<AdaptComparison> compare_adapted_head(const Model& model, const eval::LabelledFrames& frames,
                                             const std::string& sensor, const AdaptOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  TLV_ENSURE(o.steps >= 0 && o.steps <= 100000 && o.lr > 0 && std::isfinite(o.lr) &&
                 o.weight_decay >= 0 && o.folds >= 2 && o.threads >= 1,
             ErrorCode::kInvalidArgument,
             "adapt: steps %d (0..100000), lr %g (> 0), weight decay %g (>= 0), folds %d (>= 2), "
             "threads %d (>= 1)",
             o.steps, static_cast<double>(o.lr), static_cast<double>(o.weight_decay), o.folds,
             o.threads);
  torch::set_num_threads(o.threads);
  torch::manual_seed(o.seed);
  TLV_ASSIGN_OR_RETURN(TrainState state, load_checkpoint(o.checkpoint));
  EncoderNet net = state.student;
  const auto convs = static_cast<int32_t>(net->convs.size());
  TLV_ENSURE(o.layers >= 1 && o.layers <= convs, ErrorCode::kInvalidArgument,
             "adapt: --layers %d: the encoder of %s has %d conv layers", o.layers,
             o.checkpoint.c_str(), convs);

  TLV_ASSIGN_OR_RETURN(torch::Tensor x, model_inputs(model, frames, sensor));
  AdaptComparison c;
  // The checkpoint must be the encoder the model runs: compared on these very frames.
  eval::EmbedderOptions reference;
  reference.executor = ExecutorKind::kReference;
  TLV_ASSIGN_OR_RETURN(eval::FrameFeatures f,
                       eval::frame_features(model, frames, sensor, reference));
  const torch::Tensor e = embed(net, x).contiguous();
  TLV_ENSURE(e.size(1) == f.dim, ErrorCode::kShapeMismatch,
             "adapt: %s embeds into %lld values, the model into %d: not the model's checkpoint",
             o.checkpoint.c_str(), static_cast<long long>(e.size(1)), f.dim);
  c.encoder_cosine = min_row_cosine(e, torch::tensor(f.embeddings).view({-1, f.dim}));
  TLV_ENSURE(c.encoder_cosine >= kMinEncoderCosine, ErrorCode::kInvalidArgument,
             "adapt: %s does not compute the model's embeddings (smallest cosine %.4f on these "
             "frames, at least %.3f expected): give the checkpoint the model was exported from",
             o.checkpoint.c_str(), c.encoder_cosine, kMinEncoderCosine);

  const auto classes = static_cast<int32_t>(frames.classes.size());
  const eval::GroupedRows rows{f.embeddings, f.dim, f.labels, classes, f.groups, frames.classes};
  eval::CvOptions cv;
  cv.folds = o.folds;
  cv.seed = o.seed;
  TLV_ASSIGN_OR_RETURN(eval::CvResult linear, eval::cross_validate(rows, cv));
  c.n = linear.n;
  c.groups = linear.groups;
  c.folds = linear.folds;
  c.classes = classes;
  c.majority = linear.majority;
  c.steps = o.steps;

  std::vector<int32_t> adapted(f.labels.size(), -1);
  int64_t trained_params = 0;
  for (int32_t k = 0; k < linear.folds; ++k) {
    std::vector<int64_t> train_rows;
    for (size_t i = 0; i < linear.fold.size(); ++i)
      if (linear.fold[i] != k) train_rows.push_back(static_cast<int64_t>(i));
    double start = 0, end = 0;
    TLV_ASSIGN_OR_RETURN(std::vector<int32_t> p,
                         adapted_fold(o, x, f.labels, f.groups, frames.classes, train_rows, classes,
                                      trained_params, start, end));
    c.fit_loss_start += start / linear.folds;
    c.fit_loss_end += end / linear.folds;
    for (size_t i = 0; i < linear.fold.size(); ++i)
      if (linear.fold[i] == k) adapted[i] = p[i];
  }
  std::vector<uint8_t> linear_right, adapted_right;
  c.linear = score(linear.predicted, f.labels, f.groups, classes, o.seed, linear_right);
  c.adapted = score(adapted, f.labels, f.groups, classes, o.seed, adapted_right);
  for (size_t i = 0; i < linear_right.size(); ++i) {
    c.adapted_only_right += adapted_right[i] && !linear_right[i] ? 1 : 0;
    c.linear_only_right += linear_right[i] && !adapted_right[i] ? 1 : 0;
  }
  int64_t total = 0;
  for (const torch::Tensor& p : net->parameters()) total += p.numel();
  char what[160];
  std::snprintf(what, sizeof what,
                "the last %d conv layer(s) + FC: %lld of %lld encoder parameters", o.layers,
                static_cast<long long>(trained_params), static_cast<long long>(total));
  c.trained = what;
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

std::string format_adapt_comparison(const AdaptComparison& c, const std::string& head) {
  char buf[1536];
  const bool pays = c.adapted.accuracy > c.linear.accuracy && c.adapted.ci_low > c.linear.accuracy;
  std::snprintf(
      buf, sizeof buf,
      "head '%s': %lld frames, %lld groups, %d classes, %d grouped folds (majority %.1f %%)\n"
      "encoder check: the checkpoint computes the model's embeddings (smallest cosine %.5f)\n"
      "  linear head (frozen encoder)   %5.1f %%  95 %% CI [%.1f, %.1f]  balanced %.1f %%\n"
      "  adapted (%s)\n"
      "                                 %5.1f %%  95 %% CI [%.1f, %.1f]  balanced %.1f %%\n"
      "  paired: %lld frames right only when adapted, %lld only with the linear head\n"
      "  fitting rows' cross-entropy %.3f -> %.3f over %d steps (mean over folds)\n"
      "verdict: %s (fp32; %.1f s)\n",
      head.c_str(), static_cast<long long>(c.n), static_cast<long long>(c.groups), c.classes,
      c.folds, 100 * c.majority, c.encoder_cosine, 100 * c.linear.accuracy, 100 * c.linear.ci_low,
      100 * c.linear.ci_high, 100 * c.linear.balanced_accuracy, c.trained.c_str(),
      100 * c.adapted.accuracy, 100 * c.adapted.ci_low, 100 * c.adapted.ci_high,
      100 * c.adapted.balanced_accuracy, static_cast<long long>(c.adapted_only_right),
      static_cast<long long>(c.linear_only_right), c.fit_loss_start, c.fit_loss_end, c.steps,
      pays ? "adapting pays on these frames (its interval lies above the linear head's "
             "accuracy); this version does not write the adapted model, and int8 is unchecked"
           : "adapting does not pay here: keep the linear head (`heads fit --images`)",
      c.seconds);
  return buf;
}

}  // namespace tlvlink::trainer
