#include <turbojpeg.h>

#include <utility>

#include "tlvlink/image/jpeg.h"

#include "tlvlink/image/decode_budget.h"

namespace tlvlink::image {

int32_t jpeg_scaled_size(int32_t size, int32_t scale_denominator) {
  const tjscalingfactor f{1, scale_denominator};
  return TJSCALED(size, f);
}

bool jpeg_scale_supported(int32_t d) { return d == 1 || d == 2 || d == 4 || d == 8; }

JpegDecoder::JpegDecoder(JpegDecoder&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)) {}

JpegDecoder& JpegDecoder::operator=(JpegDecoder&& other) noexcept {
  if (this != &other) {
    if (handle_ != nullptr) tjDestroy(handle_);
    handle_ = std::exchange(other.handle_, nullptr);
  }
  return *this;
}

JpegDecoder::~JpegDecoder() {
  if (handle_ != nullptr) tjDestroy(handle_);
}

Status JpegDecoder::reset_after(Status status, const char* what) {
  if (status.ok()) return status;
  // A fresh handle (an allocation, on this error path only) keeps one bad frame from spoiling
  // the next.
  if (handle_ != nullptr) tjDestroy(handle_);
  handle_ = tjInitDecompress();
  if (handle_ == nullptr) {
    return status.error().with_context("%s: and tjInitDecompress failed afterwards", what);
  }
  return status;
}

Result<JpegHeader> JpegDecoder::read_header(std::span<const uint8_t> jpeg, const char* what) {
  if (handle_ == nullptr) handle_ = tjInitDecompress();
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "%s: tjInitDecompress failed", what);
  TLV_ENSURE(!jpeg.empty(), ErrorCode::kFormat, "%s: empty JPEG data (0 bytes)", what);
  // tj* take non-const input pointers for historical reasons; they do not write to the input.
  auto* data = const_cast<unsigned char*>(jpeg.data());
  int width = 0, height = 0, subsamp = 0, colorspace = 0;
  if (tjDecompressHeader3(handle_, data, jpeg.size(), &width, &height, &subsamp, &colorspace) !=
      0) {
    return reset_after(Error::make(ErrorCode::kFormat, "%s: not a readable JPEG (%zu bytes): %s",
                                   what, jpeg.size(), tjGetErrorStr2(handle_)),
                       what)
        .error();
  }
  // libjpeg only warns when the data ends inside the header: no frame size was read.
  if (width <= 0 || height <= 0) {
    return reset_after(Error::make(ErrorCode::kFormat, "%s: incomplete JPEG header (%zu bytes): %s",
                                   what, jpeg.size(), tjGetErrorStr2(handle_)),
                       what)
        .error();
  }
  TLV_ENSURE(width <= kMaxJpegSide && height <= kMaxJpegSide, ErrorCode::kFormat,
             "%s: JPEG size %dx%d outside 1..%d", what, width, height, kMaxJpegSide);
  // Before any caller sizes a buffer from the header (decode_budget.h).
  TLV_TRY(check_decode_budget(width, height, 3, jpeg.size(), kJpegMaxRatio, "JPEG", what));
  return JpegHeader{width, height};
}

Status JpegDecoder::decode_rgb(std::span<const uint8_t> jpeg, int32_t scale_denominator,
                               uint8_t* out, size_t out_bytes, size_t stride, const char* what,
                               JpegHeader expect) {
  TLV_ENSURE(jpeg_scale_supported(scale_denominator), ErrorCode::kInvalidArgument,
             "%s: JPEG scale 1/%d not offered (1, 2, 4 or 8)", what, scale_denominator);
  TLV_ASSIGN_OR_RETURN(const JpegHeader h, read_header(jpeg, what));
  TLV_ENSURE(expect.width <= 0 || (h.width == expect.width && h.height == expect.height),
             ErrorCode::kFormat, "%s: JPEG frame is %dx%d, expected %dx%d", what, h.width, h.height,
             expect.width, expect.height);
  const int32_t w = jpeg_scaled_size(h.width, scale_denominator);
  const int32_t hh = jpeg_scaled_size(h.height, scale_denominator);
  const size_t row = stride != 0 ? stride : static_cast<size_t>(w) * 3;
  TLV_ENSURE(row >= static_cast<size_t>(w) * 3 &&
                 out_bytes >= row * static_cast<size_t>(hh - 1) + static_cast<size_t>(w) * 3,
             ErrorCode::kShapeMismatch, "%s: a %dx%d RGB image does not fit %zu bytes", what, w, hh,
             out_bytes);
  // STOPONWARNING: a truncated or damaged stream is reported, not silently padded with grey.
  if (tjDecompress2(handle_, const_cast<unsigned char*>(jpeg.data()), jpeg.size(), out, w,
                    static_cast<int>(row), hh, TJPF_RGB, TJFLAG_STOPONWARNING) != 0) {
    return reset_after(
        Error::make(ErrorCode::kFormat, "%s: truncated or corrupt JPEG (%dx%d, %zu bytes): %s",
                    what, h.width, h.height, jpeg.size(), tjGetErrorStr2(handle_)),
        what);
  }
  return {};
}

}  // namespace tlvlink::image
