#pragma once
// Frame preprocessing as a model's InputSpec describes it: crop, resize to the model size,
// channel order, pixel/255, (x - mean) / std. Produces the float NHWC tensor [1,H,W,C] that is
// graph input 0. This is the one code path for inference *and* calibration (quantization.md
// edge case 11); it lives in tools until the on-device pipeline needs it.

#include <span>
#include <vector>

#include "io/image.h"
#include "io/npy.h"
#include "tlvlink/error.h"
#include "tlvlink/metadata.h"

namespace tlvlink::tools {

// Background subtraction is not implemented yet: a spec asking for it is an error
// (kModelUnsupported).
Result<std::vector<float>> preprocess(const Image& image, const InputSpec& spec);

// Bilinear resize with half-pixel centres (the convention of ResizeBilinear align_corners=false).
Image resize_bilinear(const Image& image, int32_t height, int32_t width);

// A uint8 .npy of shape [H,W,C] or [1,H,W,C] (C = 1 or 3) as an Image; `name` prefixes errors.
inline constexpr int32_t kMaxImageSideForNpy = 16384;
Result<Image> image_from_npy(const NpyArray& array, const std::string& name);

}  // namespace tlvlink::tools
