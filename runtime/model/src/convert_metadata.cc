// Metadata: input spec against graph input 0, heads against the embedding, golden pairs.

#include <algorithm>
#include <cmath>

#include "model_internal.h"

namespace tlvlink::model_internal {
namespace {

std::string_view view(const flatbuffers::String* s) {
  return s == nullptr ? std::string_view() : std::string_view(s->c_str(), s->size());
}

std::span<const float> floats(const flatbuffers::Vector<float>* v) {
  return v == nullptr ? std::span<const float>() : std::span<const float>(v->data(), v->size());
}

Status check_finite_values(std::span<const float> values, const char* what, std::string_view name) {
  for (size_t i = 0; i < values.size(); ++i) {
    TLV_ENSURE(std::isfinite(values[i]), ErrorCode::kModelInvalidMetadata,
               "%s '%.*s' value %zu is not finite", what, static_cast<int>(name.size()),
               name.data(), i);
  }
  return {};
}

std::vector<std::string_view> strings(
    const flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>* v) {
  std::vector<std::string_view> out;
  if (v == nullptr) return out;
  out.reserve(v->size());
  for (uint32_t i = 0; i < v->size(); ++i) out.push_back(view(v->Get(i)));
  return out;
}

Status convert_input_spec(const fb::InputSpec* in, const Graph& graph, InputSpec& out) {
  if (in == nullptr) return {};
  out.height = in->height();
  out.width = in->width();
  out.channels = in->channels();
  out.crop_x = in->crop_x();
  out.crop_y = in->crop_y();
  out.crop_w = in->crop_w();
  out.crop_h = in->crop_h();
  out.background_subtraction = in->background_subtraction();
  const int order = static_cast<int>(in->channel_order());
  const int filter = static_cast<int>(in->resize_filter());
  TLV_ENSURE(order >= 0 && order <= 2 && filter >= 0 && filter <= 2,
             ErrorCode::kModelInvalidMetadata,
             "input spec has unknown channel order %d or resize filter %d", order, filter);
  out.channel_order = static_cast<ChannelOrder>(order);
  out.resize_filter = static_cast<ResizeFilter>(filter);
  TLV_ENSURE(out.height >= 1 && out.width >= 1 && (out.channels == 1 || out.channels == 3),
             ErrorCode::kModelInvalidMetadata,
             "input spec %dx%dx%d: need positive size, 1 or 3 channels", out.height, out.width,
             out.channels);
  TLV_ENSURE(out.crop_x >= 0 && out.crop_y >= 0 && out.crop_w >= 0 && out.crop_h >= 0 &&
                 (out.crop_w == 0) == (out.crop_h == 0),
             ErrorCode::kModelInvalidMetadata, "input spec crop %d,%d %dx%d is invalid", out.crop_x,
             out.crop_y, out.crop_w, out.crop_h);
  out.mean = floats(in->mean());
  out.std = floats(in->std());
  const auto channels = static_cast<size_t>(out.channels);
  TLV_ENSURE(out.mean.size() == channels && out.std.size() == channels,
             ErrorCode::kModelInvalidMetadata,
             "input spec has %zu means and %zu stds for %d channels", out.mean.size(),
             out.std.size(), out.channels);
  for (size_t c = 0; c < channels; ++c) {
    TLV_ENSURE(std::isfinite(out.mean[c]) && std::isfinite(out.std[c]) && out.std[c] > 0.0f,
               ErrorCode::kModelInvalidMetadata, "input spec channel %zu mean %g std %g invalid", c,
               static_cast<double>(out.mean[c]), static_cast<double>(out.std[c]));
  }
  const Shape& s = graph.tensor(graph.inputs[0]).shape;
  TLV_ENSURE(s.rank == 4 && s[1] == out.height && s[2] == out.width && s[3] == out.channels,
             ErrorCode::kModelInvalidMetadata,
             "input spec %dx%dx%d does not match graph input 0 %s", out.height, out.width,
             out.channels, shape_label(s).text);
  return {};
}

// Trust record of a head: fractions must be finite and in [0, 1], at least one item scored.
Status convert_trust(const fb::HeadTrust* t, const char* what, std::string_view name,
                     HeadTrust& out) {
  if (t == nullptr) return {};
  out = HeadTrust{};
  out.present = true;
  out.accuracy = t->accuracy();
  out.majority = t->majority();
  out.n = t->n();
  out.test_set = view(t->test_set());
  const bool fractions = std::isfinite(out.accuracy) && std::isfinite(out.majority) &&
                         out.accuracy >= 0.0f && out.accuracy <= 1.0f && out.majority >= 0.0f &&
                         out.majority <= 1.0f;
  TLV_ENSURE(fractions && out.n >= 1, ErrorCode::kModelInvalidMetadata,
             "%s '%.*s' trust record: accuracy %g and majority %g must be in [0, 1], n %lld >= 1",
             what, static_cast<int>(name.size()), name.data(), static_cast<double>(out.accuracy),
             static_cast<double>(out.majority), static_cast<long long>(out.n));
  out.balanced_accuracy = t->balanced_accuracy();
  out.ci_low = t->accuracy_ci_low();
  out.ci_high = t->accuracy_ci_high();
  out.groups = t->groups();
  out.baseline_accuracy = t->baseline_accuracy();
  out.baseline = view(t->baseline());
  // The cross-validated fields are optional (-1: absent); present ones are fractions, and an
  // interval holds its accuracy.
  const auto optional_fraction = [](float v) {
    return v == -1.0f || (std::isfinite(v) && v >= 0.0f && v <= 1.0f);
  };
  const bool interval = (out.ci_low == -1.0f) == (out.ci_high == -1.0f) &&
                        (out.ci_low == -1.0f || (out.ci_low <= out.accuracy + 1e-6f &&
                                                 out.accuracy <= out.ci_high + 1e-6f));
  TLV_ENSURE(optional_fraction(out.balanced_accuracy) && optional_fraction(out.ci_low) &&
                 optional_fraction(out.ci_high) && optional_fraction(out.baseline_accuracy) &&
                 interval && out.groups >= 0,
             ErrorCode::kModelInvalidMetadata,
             "%s '%.*s' trust record: balanced accuracy %g, interval [%g, %g] around %g, baseline "
             "%g must be fractions (or -1: absent) and groups %lld >= 0",
             what, static_cast<int>(name.size()), name.data(),
             static_cast<double>(out.balanced_accuracy), static_cast<double>(out.ci_low),
             static_cast<double>(out.ci_high), static_cast<double>(out.accuracy),
             static_cast<double>(out.baseline_accuracy), static_cast<long long>(out.groups));
  return {};
}

Status convert_grasp_head(const fb::GraspHead& g, size_t dim, GraspHead& head) {
  head.present = true;
  head.name = view(g.name());
  head.feature_layout = view(g.feature_layout());
  head.weight = floats(g.weight());
  head.bias = g.bias();
  // The weight count against the feature layout (embeddings and difference statistics) is
  // heads::HeadEvaluator::create's check, which every user of the head and load-time
  // verification (golden head outputs) runs.
  TLV_ENSURE(dim >= 1 && !head.weight.empty() && std::isfinite(head.bias),
             ErrorCode::kModelInvalidMetadata,
             "grasp head '%.*s' has %zu weights and bias %g (embedding dimension %zu)",
             static_cast<int>(head.name.size()), head.name.data(), head.weight.size(),
             static_cast<double>(g.bias()), dim);
  TLV_TRY(check_finite_values(head.weight, "grasp head", head.name));
  return convert_trust(g.trust(), "grasp head", head.name, head.trust);
}

// A linear head reading `inputs` values: the embedding (a per-frame head) or a press's features.
Result<LinearHead> convert_linear_head(const fb::LinearHead& h, size_t inputs, const char* what) {
  LinearHead head{view(h.name()),    strings(h.labels()), floats(h.weight()), floats(h.bias()), {},
                  view(h.features())};
  const size_t n = head.labels.size();
  TLV_ENSURE(n >= 1 && inputs >= 1 && head.weight.size() == n * inputs && head.bias.size() == n,
             ErrorCode::kModelInvalidMetadata,
             "%s '%.*s': %zu labels need %zu weights and %zu biases (%zu inputs), has %zu and %zu",
             what, static_cast<int>(head.name.size()), head.name.data(), n, n * inputs, n, inputs,
             head.weight.size(), head.bias.size());
  TLV_TRY(check_finite_values(head.weight, what, head.name));
  TLV_TRY(check_finite_values(head.bias, what, head.name));
  TLV_TRY(convert_trust(h.trust(), what, head.name, head.trust));
  return head;
}

// Press heads: the one feature layout a runtime computes, names no per-frame head has (heads are
// selected and reported by name).
Status convert_press_heads(const fb::Metadata& m, Metadata& out) {
  if (m.press_heads() == nullptr) return {};
  const auto dim = static_cast<size_t>(out.embedding_dim);
  for (const fb::LinearHead* h : *m.press_heads()) {
    TLV_ASSIGN_OR_RETURN(LinearHead head,
                         convert_linear_head(*h, kPressFeatureBlocks * dim, "press head"));
    TLV_ENSURE(head.features == kPressFeatures, ErrorCode::kModelInvalidMetadata,
               "press head '%.*s' reads '%.*s'; this runtime computes '%.*s'",
               static_cast<int>(head.name.size()), head.name.data(),
               static_cast<int>(head.features.size()), head.features.data(),
               static_cast<int>(kPressFeatures.size()), kPressFeatures.data());
    const auto taken = [&](const auto& heads) {
      return std::any_of(heads.begin(), heads.end(),
                         [&](const auto& o) { return o.name == head.name; });
    };
    TLV_ENSURE(!taken(out.linear_heads) && !taken(out.zero_shot_heads) && !taken(out.press_heads),
               ErrorCode::kModelInvalidMetadata,
               "press head '%.*s': another head has that name (heads are reported by name)",
               static_cast<int>(head.name.size()), head.name.data());
    out.press_heads.push_back(std::move(head));
  }
  return {};
}

Status convert_heads(const fb::Metadata& m, Metadata& out) {
  const auto dim = static_cast<size_t>(out.embedding_dim);
  if (m.linear_heads() != nullptr) {
    for (const fb::LinearHead* h : *m.linear_heads()) {
      TLV_ASSIGN_OR_RETURN(LinearHead head, convert_linear_head(*h, dim, "linear head"));
      TLV_ENSURE(head.features.empty(), ErrorCode::kModelInvalidMetadata,
                 "linear head '%.*s' declares features '%.*s': only a press head reads other "
                 "features than the embedding",
                 static_cast<int>(head.name.size()), head.name.data(),
                 static_cast<int>(head.features.size()), head.features.data());
      out.linear_heads.push_back(std::move(head));
    }
  }
  if (m.zero_shot_heads() != nullptr) {
    for (uint32_t i = 0; i < m.zero_shot_heads()->size(); ++i) {
      const fb::ZeroShotHead* h = m.zero_shot_heads()->Get(i);
      ZeroShotHead head{view(h->name()),
                        strings(h->class_names()),
                        view(h->prompt_template()),
                        floats(h->prompt_matrix()),
                        h->logit_scale(),
                        {}};
      const size_t n = head.class_names.size();
      TLV_ENSURE(n >= 1 && dim >= 1 && head.prompt_matrix.size() == n * dim &&
                     std::isfinite(head.logit_scale) && head.logit_scale > 0,
                 ErrorCode::kModelInvalidMetadata,
                 "zero-shot head '%.*s': %zu classes need a %zux%zu prompt matrix (has %zu values) "
                 "and a positive logit scale",
                 static_cast<int>(head.name.size()), head.name.data(), n, n, dim,
                 head.prompt_matrix.size());
      TLV_TRY(check_finite_values(head.prompt_matrix, "zero-shot head", head.name));
      TLV_TRY(convert_trust(h->trust(), "zero-shot head", head.name, head.trust));
      out.zero_shot_heads.push_back(std::move(head));
    }
  }
  if (const fb::GraspHead* g = m.grasp_head(); g != nullptr)
    TLV_TRY(convert_grasp_head(*g, dim, out.grasp_head));
  if (m.sensor_grasp_heads() != nullptr) {
    TLV_ENSURE(out.grasp_head.present, ErrorCode::kModelInvalidMetadata,
               "the model has %u sensor grasp heads but no grasp head (the fallback for any "
               "other sensor)",
               m.sensor_grasp_heads()->size());
    for (const fb::GraspHead* g : *m.sensor_grasp_heads()) {
      GraspHead head;
      TLV_TRY(convert_grasp_head(*g, dim, head));
      head.sensors = strings(g->sensors());
      TLV_ENSURE(head.feature_layout == out.grasp_head.feature_layout &&
                     head.weight.size() == out.grasp_head.weight.size(),
                 ErrorCode::kModelInvalidMetadata,
                 "sensor grasp head '%.*s' reads '%.*s' (%zu weights); the grasp head reads "
                 "'%.*s' (%zu): a runtime computes one feature layout for every head",
                 static_cast<int>(head.name.size()), head.name.data(),
                 static_cast<int>(head.feature_layout.size()), head.feature_layout.data(),
                 head.weight.size(), static_cast<int>(out.grasp_head.feature_layout.size()),
                 out.grasp_head.feature_layout.data(), out.grasp_head.weight.size());
      TLV_ENSURE(!head.sensors.empty(), ErrorCode::kModelInvalidMetadata,
                 "sensor grasp head '%.*s' names no sensor model",
                 static_cast<int>(head.name.size()), head.name.data());
      for (std::string_view sensor : head.sensors) {
        for (const GraspHead& other : out.sensor_grasp_heads)
          for (std::string_view taken : other.sensors)
            TLV_ENSURE(sensor != taken && !sensor.empty(), ErrorCode::kModelInvalidMetadata,
                       "sensor model '%.*s' has two sensor grasp heads (or an empty name)",
                       static_cast<int>(sensor.size()), sensor.data());
      }
      const std::span<const float> golden = floats(g->golden());
      TLV_ENSURE(golden.size() <= 1 && (golden.empty() || std::isfinite(golden[0])),
                 ErrorCode::kModelInvalidMetadata,
                 "sensor grasp head '%.*s': %zu golden values (one finite value expected)",
                 static_cast<int>(head.name.size()), head.name.data(), golden.size());
      head.has_golden = !golden.empty();
      head.golden = golden.empty() ? 0.0f : golden[0];
      out.sensor_grasp_heads.push_back(std::move(head));
    }
  }
  return convert_press_heads(m, out);
}

Status convert_golden(const fb::Metadata& m, Buffers buffers, const Graph& graph, Metadata& out) {
  const size_t in_bytes = graph.tensor(graph.inputs[0]).bytes();
  const size_t out_bytes = graph.tensor(graph.outputs[0]).bytes();
  size_t head_classes = 0;
  for (const LinearHead& h : out.linear_heads) head_classes += h.labels.size();
  for (const ZeroShotHead& h : out.zero_shot_heads) head_classes += h.class_names.size();
  const uint32_t pairs = m.golden() == nullptr ? 0 : m.golden()->size();
  for (uint32_t i = 0; i < pairs; ++i) {
    const fb::GoldenPair* g = m.golden()->Get(i);
    TLV_ENSURE(g->input() < buffers.size() && g->output() < buffers.size(),
               ErrorCode::kModelInvalidMetadata, "golden pair %u refers to buffers %u/%u of %zu", i,
               g->input(), g->output(), buffers.size());
    GoldenPair pair{buffers[g->input()], buffers[g->output()], floats(g->head_probabilities())};
    TLV_ENSURE(pair.input.size() == in_bytes && pair.output.size() == out_bytes,
               ErrorCode::kModelInvalidMetadata,
               "golden pair %u has %zu/%zu bytes, graph input 0 / output 0 need %zu/%zu", i,
               pair.input.size(), pair.output.size(), in_bytes, out_bytes);
    // Stored head outputs: one probability per class of every per-frame head, or none.
    TLV_ENSURE(pair.head_probabilities.empty() || pair.head_probabilities.size() == head_classes,
               ErrorCode::kModelInvalidMetadata,
               "golden pair %u stores %zu head probabilities, the heads have %zu classes", i,
               pair.head_probabilities.size(), head_classes);
    TLV_TRY(check_finite_values(pair.head_probabilities, "golden pair", "head probabilities"));
    out.golden.push_back(pair);
  }
  const std::span<const float> grasp = floats(m.golden_grasp());
  TLV_ENSURE(grasp.empty() || (grasp.size() == 1 && out.grasp_head.present && !out.golden.empty() &&
                               std::isfinite(grasp[0])),
             ErrorCode::kModelInvalidMetadata,
             "golden grasp output: %zu values (one finite value expected, with a grasp head and "
             "golden pairs)",
             grasp.size());
  out.has_golden_grasp = !grasp.empty();
  out.golden_grasp = grasp.empty() ? 0.0f : grasp[0];
  for (const GraspHead& h : out.sensor_grasp_heads)
    TLV_ENSURE(!h.has_golden || !out.golden.empty(), ErrorCode::kModelInvalidMetadata,
               "sensor grasp head '%.*s' stores a golden output but the model has no golden pairs",
               static_cast<int>(h.name.size()), h.name.data());
  out.golden_press = floats(m.golden_press());
  size_t press_labels = 0;
  for (const LinearHead& h : out.press_heads) press_labels += h.labels.size();
  TLV_ENSURE(
      out.golden_press.empty() || (out.golden_press.size() == press_labels && !out.golden.empty()),
      ErrorCode::kModelInvalidMetadata,
      "golden press outputs: %zu values, the press heads have %zu labels (and golden pairs "
      "are needed)",
      out.golden_press.size(), press_labels);
  return check_finite_values(out.golden_press, "golden press", "outputs");
}

}  // namespace

Status convert_metadata(const fb::Metadata* m, Buffers buffers, const Graph& graph, Metadata& out) {
  TLV_ENSURE(m != nullptr, ErrorCode::kModelInvalidMetadata, "model has no metadata");
  out.name = view(m->name());
  TLV_TRY(convert_input_spec(m->input(), graph, out.input));
  out.embedding_dim = m->embedding_dim();
  out.embedding_output = m->embedding_output();
  TLV_ENSURE(
      out.embedding_output >= 0 && static_cast<size_t>(out.embedding_output) < graph.outputs.size(),
      ErrorCode::kModelInvalidMetadata, "embedding output %d, the graph has %zu outputs",
      out.embedding_output, graph.outputs.size());
  if (out.embedding_dim != 0) {
    const Shape& s = graph.tensor(graph.outputs[static_cast<size_t>(out.embedding_output)]).shape;
    TLV_ENSURE(out.embedding_dim > 0 && s.elements() / static_cast<size_t>(s[0]) ==
                                            static_cast<size_t>(out.embedding_dim),
               ErrorCode::kModelInvalidMetadata,
               "embedding dimension %d does not match graph output %s", out.embedding_dim,
               shape_label(s).text);
  }
  TLV_TRY(convert_heads(*m, out));
  if (const fb::Provenance* p = m->provenance(); p != nullptr) {
    out.provenance = {view(p->producer()), view(p->created_utc()), view(p->training()),
                      view(p->quantization()), p->content_checksum()};
  }
  return convert_golden(*m, buffers, graph, out);
}

}  // namespace tlvlink::model_internal
