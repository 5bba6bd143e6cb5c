#pragma once
// MJPEG frames through libturbojpeg with buffers kept across frames: the encoder compresses
// into one buffer of the worst-case size (tjBufSize, TJFLAG_NOREALLOC), the decoder into one
// RGB buffer of the scaled size. The only file of the raw camera that needs libturbojpeg.

#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink::sim::internal {

class MjpegEncoder {
 public:
  MjpegEncoder() = default;
  MjpegEncoder(const MjpegEncoder&) = delete;  // owns a tjhandle and a tjAlloc buffer
  MjpegEncoder& operator=(const MjpegEncoder&) = delete;
  ~MjpegEncoder();

  // 4:2:2 chroma (UVC MJPEG cameras subsample chroma horizontally). Allocates.
  Status init(int32_t width, int32_t height, int32_t quality);
  // width * height RGB -> a baseline JPEG, valid until the next call.
  Result<std::span<const uint8_t>> encode(const uint8_t* rgb);
  size_t max_bytes() const { return capacity_; }  // tjBufSize: no frame is larger

 private:
  void* handle_ = nullptr;
  unsigned char* buffer_ = nullptr;
  size_t capacity_ = 0;
  int32_t width_ = 0, height_ = 0, quality_ = 0;
};

class MjpegDecoder {
 public:
  MjpegDecoder() = default;
  MjpegDecoder(const MjpegDecoder&) = delete;
  MjpegDecoder& operator=(const MjpegDecoder&) = delete;
  ~MjpegDecoder();

  // Frames of width x height, decoded at 1/scale_denominator (1, 2, 4, 8). Allocates.
  Status init(int32_t width, int32_t height, int32_t scale_denominator);
  // Decodes into pixels(); `what` names the stream in errors ("gelsight-mini raw frame").
  // Rejects a frame of another size and, via TJFLAG_STOPONWARNING, a truncated or corrupt one
  // (libjpeg would otherwise pad the missing rows with grey and only warn).
  // After an error the decoder starts afresh, so the next good frame decodes.
  Status decode(std::span<const uint8_t> jpeg, const char* what);
  const uint8_t* pixels() const { return pixels_.data(); }
  int32_t scaled_width() const { return scaled_width_; }
  int32_t scaled_height() const { return scaled_height_; }

 private:
  Status decode_once(std::span<const uint8_t> jpeg, const char* what);

  void* handle_ = nullptr;
  int32_t width_ = 0, height_ = 0, scale_ = 1;
  int32_t scaled_width_ = 0, scaled_height_ = 0;
  std::vector<uint8_t> pixels_;
};

// The decoded size of one axis at 1/scale_denominator (libjpeg rounds up).
int32_t jpeg_scaled_size(int32_t size, int32_t scale_denominator);

}  // namespace tlvlink::sim::internal
