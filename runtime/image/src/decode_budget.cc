#include "tlvlink/image/decode_budget.h"

namespace tlvlink::image {

Status check_decode_budget(int64_t width, int64_t height, int64_t channels, size_t file_bytes,
                           int64_t max_ratio, const char* format, const char* what) {
  const int64_t pixels = width * height;  // sides are already checked against 16384
  TLV_ENSURE(pixels <= kMaxImagePixels, ErrorCode::kFormat,
             "%s: %s declares %lldx%lld = %lld pixels, over the %lld-pixel limit "
             "(kMaxImagePixels)",
             what, format, static_cast<long long>(width), static_cast<long long>(height),
             static_cast<long long>(pixels), static_cast<long long>(kMaxImagePixels));
  const int64_t decoded = pixels * channels;
  const int64_t allowed = static_cast<int64_t>(file_bytes) * max_ratio;
  TLV_ENSURE(decoded <= allowed, ErrorCode::kFormat,
             "%s: %s of %zu bytes declares %lldx%lld (%lld decoded bytes), more than %lld "
             "decoded bytes per file byte allow",
             what, format, file_bytes, static_cast<long long>(width),
             static_cast<long long>(height), static_cast<long long>(decoded),
             static_cast<long long>(max_ratio));
  return {};
}

}  // namespace tlvlink::image
