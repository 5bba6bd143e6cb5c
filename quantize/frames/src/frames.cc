// Frames through the deployment preprocessing (frames.h).

#include "tlvlink/quantize/frames.h"

#include "tlvlink/image/image.h"
#include "tlvlink/image/preprocess.h"

namespace tlvlink::quantize {

FramePreprocessor deployment_preprocessor() {
  return [](std::span<const uint8_t> rgb, int32_t height, int32_t width,
            const InputSpec& spec) -> Result<std::vector<float>> {
    image::Image img{width, height, 3, std::vector<uint8_t>(rgb.begin(), rgb.end())};
    return image::preprocess(img, spec);
  };
}

Result<std::vector<float>> synthetic_input(const Model& model, uint64_t seed) {
  const InputSpec& spec = model.metadata().input;
  TLV_ENSURE(spec.height > 0, ErrorCode::kInvalidArgument, "model has no input spec");
  const int32_t h = spec.height + spec.height / 4, w = spec.width + spec.width / 4;
  return deployment_preprocessor()(synthetic_touch_frame(h, w, seed), h, w, spec);
}

}  // namespace tlvlink::quantize
