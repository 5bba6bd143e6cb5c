#include <vector>

#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/image.h"

namespace tlvlink::tools {
namespace {

// Largest JPEG file read_jpeg accepts: the pixel cap's RGB size (image/decode_budget.h); an
// 8 MP MJPEG frame is a few MB even at q=100.
constexpr size_t kMaxJpegFileBytes = size_t{48} << 20;

}  // namespace

Result<Image> read_jpeg(const std::string& path, int32_t scale_denominator) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_file(path, kMaxJpegFileBytes));
  return image::decode_jpeg({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, path,
                            scale_denominator);
}

Status write_jpeg(const std::string& path, const Image& img, int32_t quality) {
  auto encoded = image::encode_jpeg(img, quality);
  if (!encoded.ok()) return encoded.error().with_context("%s", path.c_str());
  return write_file(path, std::as_bytes(std::span<const uint8_t>(encoded.value())));
}

}  // namespace tlvlink::tools
