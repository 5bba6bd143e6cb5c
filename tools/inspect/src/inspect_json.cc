// The JSON form of `tlvlink inspect`.

#include <algorithm>

#include "tlvlink/head_trust.h"
#include "tlvlink/inspect/inspect.h"

namespace tlvlink::inspect {
namespace {

using nlohmann::json;

json shape_json(const Shape& s) {
  return std::vector<int32_t>(s.dims.begin(), s.dims.begin() + s.rank);
}

json quant_json(const QuantParams& q) {
  if (!q.quantized()) return nullptr;
  return {{"axis", q.axis},
          {"scale", std::vector<float>(q.scale.begin(), q.scale.end())},
          {"zero_point", std::vector<int32_t>(q.zero_point.begin(), q.zero_point.end())}};
}

json trust_json(const HeadTrust& t) {
  const TrustAssessment a = assess_head(t);
  json j = {{"level", head_trust_level_name(a.level)}};
  if (t.present) {
    j["accuracy"] = t.accuracy;
    j["majority"] = t.majority;
    j["n"] = t.n;
    j["test_set"] = t.test_set;
    j["margin"] = a.margin;
    j["required_margin"] = a.required;
    if (t.ci_low >= 0) j["accuracy_ci95"] = {t.ci_low, t.ci_high};
    if (t.balanced_accuracy >= 0) j["balanced_accuracy"] = t.balanced_accuracy;
    if (t.groups > 0) j["groups"] = t.groups;
    if (t.baseline_accuracy >= 0) {
      j["baseline_accuracy"] = t.baseline_accuracy;
      j["baseline"] = t.baseline;
      j["below_baseline"] = a.below_baseline;
    }
  }
  return j;
}

json integrity_json(const ModelIntegrity& integrity) {
  char hash[65], key[17];
  to_hex(integrity.hash, hash, sizeof hash);
  to_hex(integrity.key_id, key, sizeof key);
  json j = {{"hash", "blake2b-256:" + std::string(hash)}, {"signed", integrity.is_signed}};
  if (integrity.is_signed) j["key_id"] = key;
  return j;
}

json metadata_json(const Model& model) {
  const Metadata& m = model.metadata();
  const InputSpec& in = m.input;
  json heads = json::array();
  for (const LinearHead& h : m.linear_heads) {
    heads.push_back({{"kind", "linear"},
                     {"name", h.name},
                     {"labels", std::vector<std::string>(h.labels.begin(), h.labels.end())},
                     {"trust", trust_json(h.trust)}});
  }
  for (const ZeroShotHead& h : m.zero_shot_heads) {
    heads.push_back(
        {{"kind", "zero_shot"},
         {"name", h.name},
         {"logit_scale", h.logit_scale},
         {"labels", std::vector<std::string>(h.class_names.begin(), h.class_names.end())},
         {"trust", trust_json(h.trust)}});
  }
  // The grasp head, then the sensor grasp heads ("sensors": the models each was fitted on; the
  // grasp head's list is empty: any sensor).
  std::vector<const GraspHead*> grasp;
  if (m.grasp_head.present) grasp.push_back(&m.grasp_head);
  for (const GraspHead& g : m.sensor_grasp_heads) grasp.push_back(&g);
  for (const GraspHead* g : grasp) {
    heads.push_back({{"kind", "grasp"},
                     {"name", g->name},
                     {"sensors", std::vector<std::string>(g->sensors.begin(), g->sensors.end())},
                     {"feature_layout", g->feature_layout},
                     {"weights", g->weight.size()},
                     {"trust", trust_json(g->trust)}});
  }
  for (const LinearHead& h : m.press_heads) {
    heads.push_back({{"kind", "press"},
                     {"name", h.name},
                     {"labels", std::vector<std::string>(h.labels.begin(), h.labels.end())},
                     {"features", h.features},
                     {"trust", trust_json(h.trust)}});
  }
  return {{"name", m.name},
          {"schema_version", model.schema_version()},
          {"file_bytes", model.bytes().size()},
          {"input",
           {{"height", in.height},
            {"width", in.width},
            {"channels", in.channels},
            {"channel_order", channel_order_name(in.channel_order)},
            {"resize_filter", resize_filter_name(in.resize_filter)},
            {"mean", std::vector<float>(in.mean.begin(), in.mean.end())},
            {"std", std::vector<float>(in.std.begin(), in.std.end())},
            {"crop", {in.crop_x, in.crop_y, in.crop_w, in.crop_h}},
            {"background_subtraction", in.background_subtraction}}},
          {"embedding_dim", m.embedding_dim},
          {"embedding_output", m.embedding_output},
          {"heads", heads},
          {"golden_pairs", m.golden.size()},
          {"provenance",
           {{"producer", m.provenance.producer},
            {"created_utc", m.provenance.created_utc},
            {"training", m.provenance.training},
            {"quantization", m.provenance.quantization},
            {"content_checksum", m.provenance.content_checksum}}},
          {"integrity", integrity_json(model.integrity())}};
}

}  // namespace

json inspect_json(const Model& model) {
  const GraphStats stats = graph_stats(model.graph());
  const Graph& g = model.graph();
  json tensors = json::array();
  for (const Tensor& t : g.tensors) {
    tensors.push_back({{"name", t.name},
                       {"dtype", dtype_name(t.dtype)},
                       {"shape", shape_json(t.shape)},
                       {"constant", t.is_constant()},
                       {"bytes", t.bytes()},
                       {"quantization", quant_json(t.quant)}});
  }
  json ops = json::array();
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    std::vector<int32_t> inputs(op.inputs.begin(),
                                op.inputs.begin() + static_cast<std::ptrdiff_t>(op.input_count));
    ops.push_back({{"type", op_type_name(op.type)},
                   {"name", op.name},
                   {"inputs", inputs},
                   {"output", op.output},
                   {"input_shape", shape_json(g.tensor(op.inputs[0]).shape)},
                   {"output_shape", shape_json(g.tensor(op.output).shape)},
                   {"macs", stats.ops[i].macs},
                   {"weight_bytes", stats.ops[i].weight_bytes},
                   {"activation_bytes", stats.ops[i].activation_bytes}});
  }
  return {{"metadata", metadata_json(model)},
          {"inputs", g.inputs},
          {"outputs", g.outputs},
          {"tensors", tensors},
          {"operators", ops},
          {"totals",
           {{"macs", stats.macs},
            {"mmac", static_cast<double>(stats.macs) / 1e6},
            {"parameters", stats.parameters},
            {"weight_bytes", stats.weight_bytes},
            {"peak_activation_bytes", stats.peak_activation_bytes}}}};
}

}  // namespace tlvlink::inspect
