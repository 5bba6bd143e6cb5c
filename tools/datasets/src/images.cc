#include "images.h"

#include <sys/stat.h>

#include <utility>

#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/image.h"

namespace tlvlink::datasets {
namespace {

tools::Image to_tool_image(const RgbImage& image) {
  tools::Image out;
  out.width = image.width;
  out.height = image.height;
  out.channels = 3;
  out.pixels = image.rgb;
  return out;
}

void take_tool_image(tools::Image&& image, RgbImage& out) {
  out.width = image.width;
  out.height = image.height;
  out.rgb = std::move(image.pixels);
}

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

}  // namespace

Status check_image(const RgbImage& image, const std::string& what) {
  TLV_ENSURE(image.height >= 1 && image.width >= 1 && image.height <= image::kMaxJpegSide &&
                 image.width <= image::kMaxJpegSide,
             ErrorCode::kInvalidArgument, "%s: image size %dx%d outside 1..%d", what.c_str(),
             image.width, image.height, image::kMaxJpegSide);
  const size_t need =
      static_cast<size_t>(image.height) * static_cast<size_t>(image.width) * size_t{3};
  TLV_ENSURE(image.rgb.size() == need, ErrorCode::kInvalidArgument,
             "%s: %zu RGB bytes for %dx%d (expected %zu)", what.c_str(), image.rgb.size(),
             image.width, image.height, need);
  return {};
}

Result<int64_t> write_jpeg_image(const std::string& path, const RgbImage& image, int32_t quality,
                                 bool full_chroma) {
  TLV_TRY(check_image(image, path));
  auto encoded = image::encode_jpeg(to_tool_image(image), quality, full_chroma);
  if (!encoded.ok()) return encoded.error().with_context("%s", path.c_str());
  TLV_TRY(tools::write_file(path, std::as_bytes(std::span<const uint8_t>(encoded.value()))));
  return static_cast<int64_t>(encoded.value().size());
}

Status jpeg_round_trip(RgbImage& image, int32_t quality) {
  TLV_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes,
                       image::encode_jpeg(to_tool_image(image), quality));
  TLV_ASSIGN_OR_RETURN(tools::Image decoded, image::decode_jpeg(bytes, "camera JPEG stage"));
  take_tool_image(std::move(decoded), image);
  return {};
}

bool load_jpeg_image(const std::string& path, int32_t scale_denominator, RgbImage& out,
                     LoadReport& report) {
  if (!file_exists(path)) {
    report.add({ProblemKind::kMissingFile, path, 0, "not found"});
    return false;
  }
  auto image = tools::read_jpeg(path, scale_denominator);
  if (!image.ok()) {
    report.add({ProblemKind::kCorruptFile, path, 0, image.error().message()});
    return false;
  }
  take_tool_image(std::move(image).value(), out);
  return true;
}

RgbImage rotate_quarter_turns(const RgbImage& image, int32_t quarter_turns) {
  const int32_t k = ((quarter_turns % 4) + 4) % 4;
  if (k == 0) return image;
  const int32_t h = image.height, w = image.width;
  RgbImage out;
  out.height = k == 2 ? h : w;
  out.width = k == 2 ? w : h;
  out.rgb.resize(image.rgb.size());
  for (int32_t y = 0; y < h; ++y) {
    for (int32_t x = 0; x < w; ++x) {
      // Counterclockwise by 90: (y, x) -> (w - 1 - x, y); by 180: (h - 1 - y, w - 1 - x);
      // by 270: (x, h - 1 - y).
      int32_t oy = 0, ox = 0;
      if (k == 1) {
        oy = w - 1 - x;
        ox = y;
      } else if (k == 2) {
        oy = h - 1 - y;
        ox = w - 1 - x;
      } else {
        oy = x;
        ox = h - 1 - y;
      }
      const size_t src =
          (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 3;
      const size_t dst =
          (static_cast<size_t>(oy) * static_cast<size_t>(out.width) + static_cast<size_t>(ox)) * 3;
      for (size_t c = 0; c < 3; ++c) out.rgb[dst + c] = image.rgb[src + c];
    }
  }
  return out;
}

}  // namespace tlvlink::datasets
