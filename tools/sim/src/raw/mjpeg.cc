#include "raw/mjpeg.h"

#include <turbojpeg.h>

namespace tlvlink::sim::internal {

int32_t jpeg_scaled_size(int32_t size, int32_t scale_denominator) {
  const tjscalingfactor f{1, scale_denominator};
  return TJSCALED(size, f);
}

MjpegEncoder::~MjpegEncoder() {
  if (buffer_ != nullptr) tjFree(buffer_);
  if (handle_ != nullptr) tjDestroy(handle_);
}

Status MjpegEncoder::init(int32_t width, int32_t height, int32_t quality) {
  TLV_ENSURE(quality >= 1 && quality <= 100, ErrorCode::kInvalidArgument,
             "raw MJPEG quality %d outside [1, 100]", quality);
  width_ = width;
  height_ = height;
  quality_ = quality;
  if (handle_ == nullptr) handle_ = tjInitCompress();
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "raw MJPEG: tjInitCompress failed");
  const unsigned long size = tjBufSize(width, height, TJSAMP_422);
  TLV_ENSURE(size != static_cast<unsigned long>(-1), ErrorCode::kInvalidArgument,
             "raw MJPEG: no buffer size for %dx%d", width, height);
  if (buffer_ != nullptr) tjFree(buffer_);
  // Address space only: pages are touched as a frame's bytes are written.
  buffer_ = tjAlloc(static_cast<int>(size));
  TLV_ENSURE(buffer_ != nullptr, ErrorCode::kOutOfMemory, "raw MJPEG: %lu-byte buffer", size);
  capacity_ = size;
  return {};
}

Result<std::span<const uint8_t>> MjpegEncoder::encode(const uint8_t* rgb) {
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "raw MJPEG: no compressor");
  unsigned char* out = buffer_;
  unsigned long size = capacity_;
  if (tjCompress2(handle_, rgb, width_, 0, height_, TJPF_RGB, &out, &size, TJSAMP_422, quality_,
                  TJFLAG_NOREALLOC) != 0) {
    const Error e = Error::make(ErrorCode::kFormat, "raw MJPEG encode %dx%d q%d: %s", width_,
                                height_, quality_, tjGetErrorStr2(handle_));
    tjDestroy(handle_);  // start the next frame from a clean handle (see the decoder)
    handle_ = tjInitCompress();
    return e;
  }
  return std::span<const uint8_t>(out, size);
}

MjpegDecoder::~MjpegDecoder() {
  if (handle_ != nullptr) tjDestroy(handle_);
}

Status MjpegDecoder::init(int32_t width, int32_t height, int32_t scale_denominator) {
  TLV_ENSURE(scale_denominator == 1 || scale_denominator == 2 || scale_denominator == 4 ||
                 scale_denominator == 8,
             ErrorCode::kInvalidArgument, "raw MJPEG decode scale 1/%d (1, 2, 4 or 8)",
             scale_denominator);
  if (handle_ == nullptr) handle_ = tjInitDecompress();
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "raw MJPEG: tjInitDecompress failed");
  width_ = width;
  height_ = height;
  scale_ = scale_denominator;
  scaled_width_ = jpeg_scaled_size(width, scale_denominator);
  scaled_height_ = jpeg_scaled_size(height, scale_denominator);
  pixels_.assign(static_cast<size_t>(scaled_width_) * static_cast<size_t>(scaled_height_) * 3, 0);
  return {};
}

Status MjpegDecoder::decode(std::span<const uint8_t> jpeg, const char* what) {
  Status st = decode_once(jpeg, what);
  if (!st.ok()) {
    // libjpeg-turbo 2.1 leaves a handle whose header read failed mid-stream in that state: the
    // next, valid frame would then read as 0x0. A fresh handle (an allocation, on this error
    // path only) keeps one bad frame from spoiling the next.
    tjDestroy(handle_);
    handle_ = tjInitDecompress();
    if (handle_ == nullptr) {
      return st.error().with_context("%s: and tjInitDecompress failed afterwards", what);
    }
  }
  return st;
}

Status MjpegDecoder::decode_once(std::span<const uint8_t> jpeg, const char* what) {
  TLV_ENSURE(handle_ != nullptr, ErrorCode::kOutOfMemory, "%s: no decompressor", what);
  TLV_ENSURE(!jpeg.empty(), ErrorCode::kFormat, "%s: empty MJPEG frame (0 bytes)", what);
  // tj* take non-const input pointers for historical reasons; they do not write to it.
  auto* data = const_cast<unsigned char*>(jpeg.data());
  int width = 0, height = 0, subsamp = 0, colorspace = 0;
  if (tjDecompressHeader3(handle_, data, jpeg.size(), &width, &height, &subsamp, &colorspace) !=
      0) {
    return Error::make(ErrorCode::kFormat, "%s: unreadable JPEG header (%zu bytes): %s", what,
                       jpeg.size(), tjGetErrorStr2(handle_));
  }
  // libjpeg only warns when the data ends inside the header: no frame size was read.
  TLV_ENSURE(width > 0 && height > 0, ErrorCode::kFormat,
             "%s: incomplete JPEG header (%zu bytes): %s", what, jpeg.size(),
             tjGetErrorStr2(handle_));
  TLV_ENSURE(width == width_ && height == height_, ErrorCode::kFormat,
             "%s: MJPEG frame is %dx%d, the sensor emits %dx%d", what, width, height, width_,
             height_);
  if (tjDecompress2(handle_, data, jpeg.size(), pixels_.data(), scaled_width_, 0, scaled_height_,
                    TJPF_RGB, TJFLAG_STOPONWARNING) != 0) {
    return Error::make(ErrorCode::kFormat, "%s: truncated or corrupt MJPEG frame (%zu bytes): %s",
                       what, jpeg.size(), tjGetErrorStr2(handle_));
  }
  return {};
}

}  // namespace tlvlink::sim::internal
