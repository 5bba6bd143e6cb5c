#pragma once
// `tlvlink inspect` pieces shared between the text and JSON forms.

#include <string>

#include <nlohmann/json.hpp>

#include "cli/op_stats.h"
#include "tlvlink/model.h"

namespace tlvlink::cli {

// "per-tensor scale 0.0235 zp -128" / "per-channel axis 0 (64): scale 1.2e-04..3.1e-02, zp 0" / "-"
std::string quant_summary(const Tensor& tensor);
std::string channel_order_name(ChannelOrder order);
std::string resize_filter_name(ResizeFilter filter);

nlohmann::json inspect_json(const Model& model, const GraphStats& stats);

}  // namespace tlvlink::cli
