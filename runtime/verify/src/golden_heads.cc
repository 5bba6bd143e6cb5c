// Head outputs on the golden pairs' stored embeddings (golden_heads.h).

#include "tlvlink/verify/golden_heads.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tlvlink/heads.h"
#include "tlvlink/verify/compare.h"

namespace tlvlink::verify {
namespace {

// Golden output `pair` as the embedding: floats, int8 dequantized (what the board feeds the heads).
void embedding_of(const Model& model, size_t pair, std::vector<float>& out) {
  const Tensor& t = model.graph().tensor(model.graph().outputs[0]);
  const std::span<const std::byte> bytes = model.metadata().golden[pair].output;
  out.resize(bytes.size() / dtype_size(t.dtype));
  for (size_t i = 0; i < out.size(); ++i) out[i] = output_value(t, bytes, i);
}

}  // namespace

bool golden_heads_apply(const Model& model) {
  const Metadata& m = model.metadata();
  const bool any_head = !m.linear_heads.empty() || !m.zero_shot_heads.empty() ||
                        m.grasp_head.present || !m.press_heads.empty();
  const Tensor& out = model.graph().tensor(model.graph().outputs[0]);
  return !m.golden.empty() && any_head && m.embedding_output == 0 && m.embedding_dim > 0 &&
         out.shape.elements() == static_cast<size_t>(m.embedding_dim);
}

Result<GoldenHeadOutputs> golden_head_outputs(const Model& model) {
  GoldenHeadOutputs out;
  if (!golden_heads_apply(model)) return out;
  TLV_ASSIGN_OR_RETURN(heads::HeadEvaluator eval, heads::HeadEvaluator::create(model.metadata()));
  const size_t n = model.metadata().golden.size();
  std::vector<std::vector<float>> embeddings(n);
  for (size_t p = 0; p < n; ++p) {
    embedding_of(model, p, embeddings[p]);
    TLV_TRY(eval.evaluate(embeddings[p]));
    std::vector<float> probabilities;
    for (const heads::HeadResult& r : eval.results().first(eval.per_frame_count())) {
      probabilities.insert(probabilities.end(), r.probabilities.begin(), r.probabilities.end());
    }
    out.pairs.push_back(std::move(probabilities));
  }
  if (eval.has_press()) {
    TLV_TRY(eval.evaluate_press(embeddings[0], embeddings[n > 1 ? 1 : 0]));
    for (const heads::HeadResult& r : eval.results().subspan(eval.per_frame_count()))
      out.press.insert(out.press.end(), r.probabilities.begin(), r.probabilities.end());
  }
  if (eval.has_grasp()) {
    std::vector<std::span<const float>> features;
    // Feature k reads pair k % n's embedding; a difference feature its first values (the golden
    // check is of the head's weights and arithmetic, and needs only fixed inputs).
    for (size_t k = 0; k < eval.grasp_layout().size(); ++k) {
      const auto values =
          static_cast<size_t>(heads::feature_values(eval.grasp_layout()[k], eval.embedding_dim()));
      TLV_ENSURE(values <= embeddings[k % n].size(), ErrorCode::kModelInvalidMetadata,
                 "grasp feature %zu reads %zu values, the golden embedding has %zu", k, values,
                 embeddings[k % n].size());
      features.emplace_back(embeddings[k % n].data(), values);
    }
    TLV_ASSIGN_OR_RETURN(out.grasp, eval.grasp_probability(features));
    out.has_grasp = true;
    for (size_t h = 1; h < eval.grasp_head_count(); ++h) {
      TLV_ASSIGN_OR_RETURN(const float p, eval.grasp_probability(features, h));
      out.sensor_grasp.push_back(p);
    }
  }
  return out;
}

Result<HeadCheck> check_golden_heads(const Model& model) {
  const Metadata& m = model.metadata();
  HeadCheck c;
  for (const GoldenPair& p : m.golden) c.stored = c.stored || !p.head_probabilities.empty();
  c.stored = c.stored || m.has_golden_grasp || !m.golden_press.empty();
  for (const GraspHead& h : m.sensor_grasp_heads) c.stored = c.stored || h.has_golden;
  if (!c.stored) return c;
  TLV_ENSURE(golden_heads_apply(model), ErrorCode::kModelInvalidMetadata,
             "the model stores golden head outputs but its embedding is not graph output 0");
  TLV_ASSIGN_OR_RETURN(GoldenHeadOutputs want, golden_head_outputs(model));
  const auto worse = [&c](double got, double stored) {
    // A NaN must fail, never compare as "not greater".
    const double e = std::fabs(got - stored);
    c.max_abs_error =
        std::isfinite(e) ? std::max(c.max_abs_error, e) : std::numeric_limits<double>::infinity();
  };
  for (size_t p = 0; p < m.golden.size(); ++p) {
    const std::span<const float> stored = m.golden[p].head_probabilities;
    TLV_ENSURE(stored.size() == want.pairs[p].size(), ErrorCode::kModelInvalidMetadata,
               "golden pair %zu stores %zu head probabilities, the heads give %zu", p,
               stored.size(), want.pairs[p].size());
    for (size_t i = 0; i < stored.size(); ++i)
      worse(static_cast<double>(want.pairs[p][i]), static_cast<double>(stored[i]));
  }
  TLV_ENSURE(m.has_golden_grasp == want.has_grasp, ErrorCode::kModelInvalidMetadata,
             "the golden grasp output is %s but the model %s a grasp head",
             m.has_golden_grasp ? "stored" : "missing", want.has_grasp ? "has" : "has no");
  if (want.has_grasp) worse(static_cast<double>(want.grasp), static_cast<double>(m.golden_grasp));
  for (size_t h = 0; h < m.sensor_grasp_heads.size(); ++h) {
    const GraspHead& head = m.sensor_grasp_heads[h];
    TLV_ENSURE(head.has_golden == m.has_golden_grasp, ErrorCode::kModelInvalidMetadata,
               "sensor grasp head '%.*s' %s a golden output but the grasp head %s",
               static_cast<int>(head.name.size()), head.name.data(),
               head.has_golden ? "stores" : "lacks", m.has_golden_grasp ? "does" : "does not");
    if (head.has_golden)
      worse(static_cast<double>(want.sensor_grasp[h]), static_cast<double>(head.golden));
  }
  TLV_ENSURE(m.golden_press.size() == want.press.size(), ErrorCode::kModelInvalidMetadata,
             "the model stores %zu golden press outputs, its press heads give %zu",
             m.golden_press.size(), want.press.size());
  for (size_t i = 0; i < want.press.size(); ++i)
    worse(static_cast<double>(want.press[i]), static_cast<double>(m.golden_press[i]));
  c.pass = c.max_abs_error <= c.tolerance;
  return c;
}

}  // namespace tlvlink::verify
