// JPEG artefacts: encode + decode through tools/io/jpeg.h (libturbojpeg), kept apart from the
// rest of the renderer so a board build can swap or drop it.
#include <cstring>

#include "render/camera.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"

namespace tlvlink::sim::internal {

Status jpeg_round_trip(std::vector<uint8_t>& rgb, int32_t width, int32_t height, int32_t quality,
                       int32_t passes, tools::Image& scratch) {
  scratch.width = width;
  scratch.height = height;
  scratch.channels = 3;
  scratch.pixels.assign(rgb.begin(), rgb.end());
  for (int32_t pass = 0; pass < passes; ++pass) {
    auto bytes = image::encode_jpeg(scratch, quality);
    if (!bytes.ok()) return bytes.error().with_context("simulated JPEG (quality %d)", quality);
    auto decoded = image::decode_jpeg(bytes.value(), "simulated frame");
    if (!decoded.ok()) return decoded.error().with_context("simulated JPEG (quality %d)", quality);
    TLV_ENSURE(decoded->width == width && decoded->height == height && decoded->channels == 3,
               ErrorCode::kFormat, "simulated JPEG: decoded %dx%dx%d, expected %dx%dx3",
               decoded->width, decoded->height, decoded->channels, width, height);
    scratch.pixels.swap(decoded->pixels);
  }
  std::memcpy(rgb.data(), scratch.pixels.data(), rgb.size());
  return {};
}

}  // namespace tlvlink::sim::internal
