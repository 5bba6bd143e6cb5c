#pragma once
// Host tools use the runtime's image type (runtime/image) under their own namespace, and read
// and write JPEG files through the runtime's one libturbojpeg wrapper.

#include <string>

#include "tlvlink/error.h"
#include "tlvlink/image/image.h"

namespace tlvlink::tools {

using Image = image::Image;

// JPEG files: decoded at 1/scale_denominator (1, 2, 4, 8); written as baseline JPEG, 4:2:0 for
// RGB. Errors name the path.
Result<Image> read_jpeg(const std::string& path, int32_t scale_denominator = 1);
Status write_jpeg(const std::string& path, const Image& image, int32_t quality);

}  // namespace tlvlink::tools
