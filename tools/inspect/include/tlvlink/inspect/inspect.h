#pragma once
// What `tlvlink inspect` shows about a model: metadata (input spec, heads, provenance, golden
// pairs), every tensor with its quantization, every operator with its MACs, weight and
// activation bytes, and the totals; as text tables or as one JSON object.
//
//   auto model = tools::load_model("enc.tlvm");
//   std::fputs(inspect::inspect_text(**model).c_str(), stdout);

#include <string>

#include <nlohmann/json.hpp>

#include "tlvlink/inspect/graph_stats.h"
#include "tlvlink/model.h"

namespace tlvlink::inspect {

// The tables `tlvlink inspect` prints.
std::string inspect_text(const Model& model);
// The same as JSON (`tlvlink inspect --json`).
nlohmann::json inspect_json(const Model& model);

// "per-tensor scale 0.0235 zp -128" / "per-channel axis 0 (64): scale 1.2e-04..3.1e-02, zp 0" / "-"
std::string quant_summary(const Tensor& tensor);
std::string channel_order_name(ChannelOrder order);

}  // namespace tlvlink::inspect
