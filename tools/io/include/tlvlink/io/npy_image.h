#pragma once
// A uint8 .npy array as an image (infer and quantize take frames saved by NumPy).

#include <string>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy.h"

namespace tlvlink::tools {

// A uint8 .npy of shape [H,W,C] or [1,H,W,C] (C = 1 or 3) as an Image; `name` prefixes errors.
inline constexpr int32_t kMaxImageSideForNpy = 16384;
Result<Image> image_from_npy(const NpyArray& array, const std::string& name);

}  // namespace tlvlink::tools
