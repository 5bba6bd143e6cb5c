// The text form of `tlvlink inspect` (inspect.h): metadata, tensors, per-operator costs, totals.

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "tlvlink/inspect/inspect.h"
#include "tlvlink/inspect/trust_text.h"
#include "tlvlink/io/format.h"

namespace tlvlink::inspect {
namespace {

using tools::appendf;

std::string join_floats(std::span<const float> v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]).substr(0, 6);
  return "[" + s + "]";
}

void print_metadata(std::string& out, const Model& model) {
  const Metadata& m = model.metadata();
  const Provenance& p = m.provenance;
  appendf(out, "model        %.*s  (schema %u, %s)\n", static_cast<int>(m.name.size()),
          m.name.data(), model.schema_version(), tools::human_bytes(model.bytes().size()).c_str());
  appendf(out, "producer     %.*s, created %.*s\n", static_cast<int>(p.producer.size()),
          p.producer.data(), static_cast<int>(p.created_utc.size()), p.created_utc.data());
  const ModelIntegrity& integrity = model.integrity();
  char hash[65], key[17];
  to_hex(integrity.hash, hash, sizeof hash);
  to_hex(integrity.key_id, key, sizeof key);
  appendf(out, "integrity    BLAKE2b-256 %s, %s%s\n", hash,
          integrity.is_signed ? "signed by key " : "unsigned", integrity.is_signed ? key : "");
  appendf(out, "training     %.*s\n", static_cast<int>(p.training.size()), p.training.data());
  appendf(out, "quantization %.*s\n", static_cast<int>(p.quantization.size()),
          p.quantization.data());
  const InputSpec& in = m.input;
  appendf(out, "input        %dx%dx%d %s, resize %s, mean %s, std %s", in.height, in.width,
          in.channels, channel_order_name(in.channel_order).c_str(),
          resize_filter_name(in.resize_filter), join_floats(in.mean).c_str(),
          join_floats(in.std).c_str());
  if (in.crop_w > 0) appendf(out, ", crop %d,%d %dx%d", in.crop_x, in.crop_y, in.crop_w, in.crop_h);
  appendf(out, "%s\n", in.background_subtraction ? ", background subtraction" : "");
  appendf(out, "embedding    %d (graph output %d)\n", m.embedding_dim, m.embedding_output);
  for (const LinearHead& h : m.linear_heads) {
    std::string labels;
    for (size_t i = 0; i < h.labels.size(); ++i)
      labels += (i ? ", " : "") + std::string(h.labels[i]);
    appendf(out, "linear head  %.*s (%zu): %s\n             %s\n", static_cast<int>(h.name.size()),
            h.name.data(), h.labels.size(), labels.c_str(), trust_text(h.trust).c_str());
  }
  for (const ZeroShotHead& h : m.zero_shot_heads) {
    appendf(out, "zero-shot    %.*s (%zu classes, logit scale %g)\n             %s\n",
            static_cast<int>(h.name.size()), h.name.data(), h.class_names.size(),
            static_cast<double>(h.logit_scale), trust_text(h.trust).c_str());
  }
  if (m.grasp_head.present) {
    appendf(out, "grasp head   %.*s: %zu weights, layout %.*s\n             %s\n",
            static_cast<int>(m.grasp_head.name.size()), m.grasp_head.name.data(),
            m.grasp_head.weight.size(), static_cast<int>(m.grasp_head.feature_layout.size()),
            m.grasp_head.feature_layout.data(), trust_text(m.grasp_head.trust).c_str());
  }
  for (const GraspHead& g : m.sensor_grasp_heads) {
    std::string sensors;
    for (std::string_view s : g.sensors) sensors += (sensors.empty() ? "" : ", ") + std::string(s);
    appendf(out, "grasp head   %.*s for %s (fitted on those sensors only)\n             %s\n",
            static_cast<int>(g.name.size()), g.name.data(), sensors.c_str(),
            trust_text(g.trust).c_str());
  }
  for (const LinearHead& h : m.press_heads) {
    std::string labels;
    for (std::string_view l : h.labels) labels += (labels.empty() ? "" : ", ") + std::string(l);
    appendf(out, "press head   %.*s: %s over a press (%.*s)\n             %s\n",
            static_cast<int>(h.name.size()), h.name.data(), labels.c_str(),
            static_cast<int>(h.features.size()), h.features.data(), trust_text(h.trust).c_str());
  }
  appendf(out, "golden pairs %zu\n", m.golden.size());
}

void print_tensors(std::string& out, const Graph& g) {
  appendf(out, "\ntensors (%zu)\n  %4s  %-28s %-7s %-18s %-8s %s\n", g.tensors.size(), "#", "name",
          "dtype", "shape", "kind", "quantization");
  for (size_t i = 0; i < g.tensors.size(); ++i) {
    const Tensor& t = g.tensors[i];
    const auto idx = static_cast<int32_t>(i);
    const bool is_in = std::find(g.inputs.begin(), g.inputs.end(), idx) != g.inputs.end();
    const bool is_out = std::find(g.outputs.begin(), g.outputs.end(), idx) != g.outputs.end();
    const char* kind = t.is_constant() ? "const" : is_in ? "input" : is_out ? "output" : "act";
    appendf(out, "  %4zu  %-28.*s %-7s %-18s %-8s %s\n", i, static_cast<int>(t.name.size()),
            t.name.data(), dtype_name(t.dtype), tools::shape_string(t.shape).c_str(), kind,
            quant_summary(t).c_str());
  }
}

void print_operators(std::string& out, const Graph& g, const GraphStats& s) {
  appendf(out, "\noperators (%zu)\n  %4s  %-17s %-22s %-18s %-18s %10s %10s %10s\n",
          g.operators.size(), "#", "type", "name", "input", "output", "MACs", "weights",
          "act bytes");
  for (size_t i = 0; i < g.operators.size(); ++i) {
    const Operator& op = g.operators[i];
    appendf(out, "  %4zu  %-17s %-22.*s %-18s %-18s %10" PRIu64 " %10zu %10zu\n", i,
            op_type_name(op.type), static_cast<int>(op.name.size()), op.name.data(),
            tools::shape_string(g.tensor(op.inputs[0]).shape).c_str(),
            tools::shape_string(g.tensor(op.output).shape).c_str(), s.ops[i].macs,
            s.ops[i].weight_bytes, s.ops[i].activation_bytes);
  }
}

}  // namespace

std::string inspect_text(const Model& model) {
  const GraphStats stats = graph_stats(model.graph());
  std::string out;
  print_metadata(out, model);
  print_tensors(out, model.graph());
  print_operators(out, model.graph(), stats);
  appendf(out,
          "\ntotals: %.2f MMAC, %.3f M parameters, %s weights, peak activations ~%s "
          "(liveness estimate, no in-place reuse)\n",
          static_cast<double>(stats.macs) / 1e6, static_cast<double>(stats.parameters) / 1e6,
          tools::human_bytes(stats.weight_bytes).c_str(),
          tools::human_bytes(stats.peak_activation_bytes).c_str());
  return out;
}

std::string channel_order_name(ChannelOrder order) {
  return order == ChannelOrder::kRGB ? "RGB" : order == ChannelOrder::kBGR ? "BGR" : "gray";
}

std::string quant_summary(const Tensor& t) {
  const QuantParams& q = t.quant;
  if (!q.quantized()) return "-";
  char text[160];
  if (!q.per_channel()) {
    std::snprintf(text, sizeof(text), "per-tensor scale %.4g zp %d",
                  static_cast<double>(q.scale[0]), q.zero_point[0]);
    return text;
  }
  const auto [smin, smax] = std::minmax_element(q.scale.begin(), q.scale.end());
  const auto [zmin, zmax] = std::minmax_element(q.zero_point.begin(), q.zero_point.end());
  std::snprintf(text, sizeof(text), "per-channel axis %d (%zu): scale %.3g..%.3g, zp %d..%d",
                q.axis, q.scale.size(), static_cast<double>(*smin), static_cast<double>(*smax),
                *zmin, *zmax);
  return text;
}

}  // namespace tlvlink::inspect
