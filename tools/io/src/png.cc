// PNG decoding with libpng's simplified API (png_image_*), which handles every colour type.

#include "tlvlink/io/png.h"

#include <png.h>

#include <vector>

#include "tlvlink/image/decode_budget.h"
#include "tlvlink/io/file.h"

namespace tlvlink::tools {

Result<Image> decode_png(std::span<const std::byte> bytes, const std::string& name) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()) == 0) {
    return Error::make(ErrorCode::kFormat, "%s: not a readable PNG (%s)", name.c_str(),
                       png.message);
  }
  const bool gray = (png.format & PNG_FORMAT_FLAG_COLOR) == 0;
  if (png.width == 0 || png.height == 0 || png.width > kMaxPngSide || png.height > kMaxPngSide) {
    png_image_free(&png);
    return Error::make(ErrorCode::kFormat, "%s: PNG size %ux%u outside 1..%d", name.c_str(),
                       png.width, png.height, kMaxPngSide);
  }
  // Before the pixel buffer is sized from the header (a 780 KB PNG can declare 800 MB).
  const Status budget = image::check_decode_budget(
      png.width, png.height, gray ? 1 : 3, bytes.size(), image::kPngMaxRatio, "PNG", name.c_str());
  if (!budget.ok()) {
    png_image_free(&png);
    return budget.error();
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
    return Error::make(ErrorCode::kFormat, "%s: PNG decode failed (%s)", name.c_str(), why.c_str());
  }
  return image;
}

Result<Image> read_png(const std::string& path) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_file(path, kMaxPngFileBytes));
  return decode_png(bytes, path);
}

}  // namespace tlvlink::tools
