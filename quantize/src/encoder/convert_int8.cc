// convert_to_int8: the min/max entry point of calibrate.h, now a thin wrapper over the quantizer
// (quantizer.h) with its defaults (per-channel weights, no user denylist), so the reference
// encoder and `tlvlink quantize` share one converter.

#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink::quantize {

Result<ModelBuilder> convert_to_int8(const Model& fp32, std::span<const TensorRange> ranges,
                                     const Int8ConversionOptions& options) {
  QuantizerOptions o;
  o.min_activation_range = options.min_activation_range;
  o.quantization_json = options.quantization_json;
  TLV_ASSIGN_OR_RETURN(QuantizedModel q, quantize_model(fp32, ranges, o));
  return std::move(q.builder);
}

}  // namespace tlvlink::quantize
