#include <turbojpeg.h>

#include "tlvlink/image/jpeg.h"

namespace tlvlink::image {
namespace {

int tj_subsampling(JpegEncoder::Subsampling s) {
  switch (s) {
    case JpegEncoder::Subsampling::k420: return TJSAMP_420;
    case JpegEncoder::Subsampling::k422: return TJSAMP_422;
    case JpegEncoder::Subsampling::k444: return TJSAMP_444;
    case JpegEncoder::Subsampling::kGray: return TJSAMP_GRAY;
  }
  return TJSAMP_420;
}

}  // namespace

JpegEncoder::~JpegEncoder() {
  if (buffer_ != nullptr) tjFree(buffer_);
  if (handle_ != nullptr) tjDestroy(handle_);
}

Result<size_t> JpegEncoder::max_bytes(int32_t width, int32_t height, Subsampling subsampling) {
  const unsigned long size = tjBufSize(width, height, tj_subsampling(subsampling));
  TLV_ENSURE(size != static_cast<unsigned long>(-1), ErrorCode::kInvalidArgument,
             "JPEG encode: no buffer size for %dx%d", width, height);
  return static_cast<size_t>(size);
}

Result<std::span<const uint8_t>> JpegEncoder::encode(const ImageView& image, int32_t quality,
                                                     Subsampling subsampling) {
  TLV_ENSURE(quality >= 1 && quality <= 100, ErrorCode::kInvalidArgument,
             "JPEG quality %d outside 1..100", quality);
  const bool gray = subsampling == Subsampling::kGray;
  TLV_ENSURE(image.channels == (gray ? 1 : 3), ErrorCode::kInvalidArgument,
             "JPEG encode: %d channels for %s", image.channels, gray ? "gray" : "RGB");
  TLV_ENSURE(image.width >= 1 && image.height >= 1 && image.width <= kMaxJpegSide &&
                 image.height <= kMaxJpegSide,
             ErrorCode::kInvalidArgument, "JPEG encode: size %dx%d outside 1..%d", image.width,
             image.height, kMaxJpegSide);
  if (handle_ == nullptr) handle_ = tjInitCompress();
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "JPEG encode: tjInitCompress failed");
  TLV_ASSIGN_OR_RETURN(const size_t capacity, max_bytes(image.width, image.height, subsampling));
  if (capacity > capacity_) {
    if (buffer_ != nullptr) tjFree(buffer_);
    buffer_ = tjAlloc(static_cast<int>(capacity));
    capacity_ = buffer_ != nullptr ? capacity : 0;
    TLV_ENSURE(buffer_ != nullptr, ErrorCode::kOutOfMemory, "JPEG encode: %zu-byte buffer",
               capacity);
  }
  unsigned char* dst = buffer_;
  unsigned long size = capacity_;
  if (tjCompress2(handle_, image.pixels, image.width, static_cast<int>(image.row_bytes()),
                  image.height, gray ? TJPF_GRAY : TJPF_RGB, &dst, &size,
                  tj_subsampling(subsampling), quality, TJFLAG_NOREALLOC) != 0) {
    const Error e = Error::make(ErrorCode::kFormat, "JPEG encode %dx%d q%d: %s", image.width,
                                image.height, quality, tjGetErrorStr2(handle_));
    tjDestroy(handle_);  // start the next image from a clean handle (see JpegDecoder)
    handle_ = tjInitCompress();
    return e;
  }
  return std::span<const uint8_t>(dst, size);
}

}  // namespace tlvlink::image
