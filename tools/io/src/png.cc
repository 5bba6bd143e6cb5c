// PNG decoding with libpng's simplified API (png_image_*), which handles every colour type.

#include "tlvlink/io/png.h"

#include <png.h>

namespace tlvlink::tools {

Result<Image> read_png(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    return Error::make(ErrorCode::kFormat, "%s: not a readable PNG (%s)", path.c_str(), png.message);
  }
  const bool gray = (png.format & PNG_FORMAT_FLAG_COLOR) == 0;
  if (png.width == 0 || png.height == 0 || png.width > kMaxPngSide || png.height > kMaxPngSide) {
    png_image_free(&png);
    return Error::make(ErrorCode::kFormat, "%s: PNG size %ux%u outside 1..%d", path.c_str(),
                       png.width, png.height, kMaxPngSide);
  }
  png.format = gray ? PNG_FORMAT_GRAY : PNG_FORMAT_RGB;  // alpha dropped (composited on black)
  Image image;
  image.width = static_cast<int32_t>(png.width);
  image.height = static_cast<int32_t>(png.height);
  image.channels = gray ? 1 : 3;
  image.pixels.resize(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, image.pixels.data(), 0, nullptr) == 0) {
    const std::string why = png.message;
    png_image_free(&png);
    return Error::make(ErrorCode::kFormat, "%s: PNG decode failed (%s)", path.c_str(), why.c_str());
  }
  return image;
}

}  // namespace tlvlink::tools
