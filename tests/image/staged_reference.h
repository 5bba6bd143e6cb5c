#pragma once
// The staged preprocessing of 7024ac8 (see staged_reference.cc), kept as the test oracle.

#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/image/image.h"
#include "tlvlink/metadata.h"

namespace tlvlink::testing::staged {

Result<std::vector<float>> preprocess(const image::Image& image, const InputSpec& spec);
image::Image resize_bilinear(const image::Image& image, int32_t height, int32_t width);

}  // namespace tlvlink::testing::staged
