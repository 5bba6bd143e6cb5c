#include "tlvlink/heads/evaluator.h"

#include "tlvlink/head_trust.h"
#include "tlvlink/heads/head_math.h"

namespace tlvlink::heads {

const char* head_kind_name(HeadKind kind) {
  return kind == HeadKind::kZeroShot ? "zero-shot" : kind == HeadKind::kPress ? "press" : "probe";
}

bool reported_by_default(const HeadResult& result) {
  return result.kind != HeadKind::kZeroShot &&
         (result.trust == nullptr ||
          assess_head(*result.trust).level != HeadTrustLevel::kUntrusted);
}

Result<HeadEvaluator> HeadEvaluator::create(const Metadata& m) {
  TLV_ENSURE(m.embedding_dim > 0, ErrorCode::kModelInvalidMetadata,
             "the model declares no embedding dimension: it has no heads to evaluate");
  HeadEvaluator h;
  h.metadata_ = &m;
  h.dim_ = m.embedding_dim;
  const auto dim = static_cast<size_t>(m.embedding_dim);
  size_t values = 0;
  for (const LinearHead& l : m.linear_heads) {
    TLV_ENSURE(!l.labels.empty() && l.weight.size() == l.labels.size() * dim &&
                   l.bias.size() == l.labels.size(),
               ErrorCode::kModelInvalidMetadata,
               "head '%.*s': %zu labels, %zu weights, %zu biases for embedding dim %zu",
               static_cast<int>(l.name.size()), l.name.data(), l.labels.size(), l.weight.size(),
               l.bias.size(), dim);
    values += 2 * l.labels.size();
  }
  for (const ZeroShotHead& z : m.zero_shot_heads) {
    TLV_ENSURE(!z.class_names.empty() && z.prompt_matrix.size() == z.class_names.size() * dim,
               ErrorCode::kModelInvalidMetadata,
               "zero-shot head '%.*s': %zu classes, %zu prompt values for embedding dim %zu",
               static_cast<int>(z.name.size()), z.name.data(), z.class_names.size(),
               z.prompt_matrix.size(), dim);
    values += 2 * z.class_names.size();
  }
  for (const LinearHead& l : m.press_heads) {
    TLV_ENSURE(!l.labels.empty() && l.weight.size() == l.labels.size() * 2 * dim &&
                   l.bias.size() == l.labels.size(),
               ErrorCode::kModelInvalidMetadata,
               "press head '%.*s': %zu labels, %zu weights, %zu biases for 2 x embedding dim %zu",
               static_cast<int>(l.name.size()), l.name.data(), l.labels.size(), l.weight.size(),
               l.bias.size(), dim);
    values += 2 * l.labels.size();
  }
  h.scratch_.assign(values, 0.0f);
  h.press_features_.assign(m.press_heads.empty() ? 0 : 2 * dim, 0.0f);
  size_t at = 0;
  const auto add = [&](std::string_view name, HeadKind kind,
                       std::span<const std::string_view> labels, const HeadTrust& trust) {
    HeadResult r;
    r.name = name;
    r.kind = kind;
    r.labels = labels;
    r.trust = &trust;
    h.offsets_.push_back(at);
    r.logits = std::span<const float>(h.scratch_).subspan(at, labels.size());
    r.probabilities = std::span<const float>(h.scratch_).subspan(at + labels.size(), labels.size());
    at += 2 * labels.size();
    h.results_.push_back(r);
  };
  for (const LinearHead& l : m.linear_heads) add(l.name, HeadKind::kProbe, l.labels, l.trust);
  for (const ZeroShotHead& z : m.zero_shot_heads)
    add(z.name, HeadKind::kZeroShot, z.class_names, z.trust);
  h.per_frame_ = h.results_.size();
  for (const LinearHead& l : m.press_heads) add(l.name, HeadKind::kPress, l.labels, l.trust);
  if (m.grasp_head.present) {
    TLV_ASSIGN_OR_RETURN(h.grasp_layout_, parse_grasp_layout(m.grasp_head.feature_layout));
    const size_t needs = layout_values(h.grasp_layout_, m.embedding_dim);
    TLV_ENSURE(m.grasp_head.weight.size() == needs, ErrorCode::kModelInvalidMetadata,
               "grasp head has %zu weights; layout '%.*s' with embedding dim %zu needs %zu",
               m.grasp_head.weight.size(), static_cast<int>(m.grasp_head.feature_layout.size()),
               m.grasp_head.feature_layout.data(), dim, needs);
    if (has_difference(h.grasp_layout_)) {
      // The features are statistics of the model's 3-channel input (grasp_difference.h).
      TLV_ENSURE(m.input.channels == 3, ErrorCode::kModelInvalidMetadata,
                 "grasp layout '%.*s' reads difference features, which need a 3-channel "
                 "input; the model reads %d",
                 static_cast<int>(m.grasp_head.feature_layout.size()),
                 m.grasp_head.feature_layout.data(), m.input.channels);
    }
  }
  return h;
}

Status HeadEvaluator::evaluate(std::span<const float> e) {
  TLV_ENSURE(e.size() == static_cast<size_t>(dim_), ErrorCode::kShapeMismatch,
             "embedding has %zu values, the heads read %d", e.size(), dim_);
  const size_t linear = metadata_->linear_heads.size();
  for (size_t i = 0; i < per_frame_; ++i) {
    HeadResult& r = results_[i];
    const size_t n = r.labels.size();
    const std::span<float> l(scratch_.data() + offsets_[i], n);
    const std::span<float> p(scratch_.data() + offsets_[i] + n, n);
    if (i < linear) {
      const LinearHead& h = metadata_->linear_heads[i];
      linear_logits(h.weight, h.bias, e, l);
    } else {
      const ZeroShotHead& z = metadata_->zero_shot_heads[i - linear];
      zero_shot_logits(z.prompt_matrix, z.logit_scale, e, l);
    }
    r.top = softmax(l, p);
  }
  return {};
}

Status HeadEvaluator::evaluate_press(std::span<const float> peak, std::span<const float> first) {
  const auto dim = static_cast<size_t>(dim_);
  TLV_ENSURE(peak.size() == dim && first.size() == dim, ErrorCode::kShapeMismatch,
             "press features: peak %zu and first %zu values, the heads read %d each", peak.size(),
             first.size(), dim_);
  for (size_t i = 0; i < dim; ++i) {
    press_features_[i] = peak[i];
    press_features_[dim + i] = peak[i] - first[i];
  }
  for (size_t i = per_frame_; i < results_.size(); ++i) {
    HeadResult& r = results_[i];
    const size_t n = r.labels.size();
    const std::span<float> l(scratch_.data() + offsets_[i], n);
    const LinearHead& h = metadata_->press_heads[i - per_frame_];
    linear_logits(h.weight, h.bias, press_features_, l);
    r.top = softmax(l, std::span<float>(scratch_.data() + offsets_[i] + n, n));
  }
  return {};
}

size_t HeadEvaluator::grasp_head_count() const {
  return has_grasp() ? 1 + metadata_->sensor_grasp_heads.size() : 0;
}

size_t HeadEvaluator::grasp_head_for(std::string_view sensor_model) const {
  if (!has_grasp() || sensor_model.empty()) return 0;
  for (size_t h = 0; h < metadata_->sensor_grasp_heads.size(); ++h)
    for (std::string_view s : metadata_->sensor_grasp_heads[h].sensors)
      if (s == sensor_model) return h + 1;
  return 0;
}

const GraspHead& HeadEvaluator::grasp_head(size_t head) const {
  return head == 0 ? metadata_->grasp_head : metadata_->sensor_grasp_heads[head - 1];
}

std::string_view HeadEvaluator::grasp_name(size_t head) const {
  return has_grasp() && head < grasp_head_count() ? grasp_head(head).name : std::string_view();
}

Result<float> HeadEvaluator::grasp_probability(std::span<const std::span<const float>> features,
                                               size_t head) const {
  TLV_ENSURE(has_grasp(), ErrorCode::kInvalidState, "the model has no grasp head");
  TLV_ENSURE(head < grasp_head_count(), ErrorCode::kInvalidArgument,
             "grasp head %zu of %zu requested", head, grasp_head_count());
  TLV_ENSURE(features.size() == grasp_layout_.size(), ErrorCode::kShapeMismatch,
             "grasp head reads %zu features (%.*s), got %zu", grasp_layout_.size(),
             static_cast<int>(metadata_->grasp_head.feature_layout.size()),
             metadata_->grasp_head.feature_layout.data(), features.size());
  for (size_t k = 0; k < features.size(); ++k) {
    const auto want = static_cast<size_t>(feature_values(grasp_layout_[k], dim_));
    TLV_ENSURE(features[k].size() == want, ErrorCode::kShapeMismatch,
               "grasp feature %zu has %zu values, the head reads %zu there", k, features[k].size(),
               want);
  }
  const GraspHead& g = grasp_head(head);
  return sigmoid(grasp_logit(g.weight, g.bias, features));
}

std::string grasp_head_label(const HeadEvaluator& heads, size_t head) {
  std::string out(heads.grasp_name(head));
  if (head == 0 || head >= heads.grasp_head_count()) return out;
  std::string sensors;
  for (std::string_view s : heads.grasp_head(head).sensors)
    sensors += (sensors.empty() ? "" : ", ") + std::string(s);
  return out + " (fitted on " + sensors + ")";
}

}  // namespace tlvlink::heads
