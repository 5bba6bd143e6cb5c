#pragma once
// JPEG through libturbojpeg (Debian's libturbojpeg0): the one wrapper of the project.
// - JpegDecoder / JpegEncoder own a libjpeg-turbo handle each; one object per thread. They keep
//   their handle across images (the camera path decodes thousands of frames with one decoder)
//   and decode into caller-owned memory, so tlvlink allocates nothing per frame. libjpeg-turbo
//   itself mallocs and frees its per-image working memory inside every call.
// - Decoding at 1/2, 1/4 or 1/8 scale makes the IDCT do the downscale: an 8 MP MJPEG frame
//   costs a fraction of a full decode (entropy decoding of the whole stream remains).
// - A truncated or corrupt stream is an error (TJFLAG_STOPONWARNING), never grey padding; after
//   any error the decoder starts from a fresh handle (libjpeg-turbo 2.1 leaves a handle that
//   failed mid-header unusable: the next valid image would read as 0x0).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/image/image.h"

namespace tlvlink::image {

// Largest JPEG side accepted (a GelSight Mini frame is 3280x2464).
inline constexpr int32_t kMaxJpegSide = 16384;

// The decoded size of an axis at 1/scale_denominator (libjpeg rounds up).
int32_t jpeg_scaled_size(int32_t size, int32_t scale_denominator);
bool jpeg_scale_supported(int32_t scale_denominator);  // 1, 2, 4 or 8

struct JpegHeader {
  int32_t width = 0, height = 0;
};

class JpegDecoder {
 public:
  JpegDecoder() = default;
  JpegDecoder(const JpegDecoder&) = delete;  // owns a tjhandle
  JpegDecoder& operator=(const JpegDecoder&) = delete;
  JpegDecoder(JpegDecoder&& other) noexcept;
  JpegDecoder& operator=(JpegDecoder&& other) noexcept;
  ~JpegDecoder();

  // The image size from the header. `what` names the stream in errors ("mini-left frame 12").
  Result<JpegHeader> read_header(std::span<const uint8_t> jpeg, const char* what);
  // Decodes to RGB at 1/scale_denominator into `out`, rows of `stride` bytes (0: packed),
  // which must hold the scaled image (kShapeMismatch otherwise). The header's size must be
  // expect (when expect.width > 0), or the frame is rejected naming both sizes.
  Status decode_rgb(std::span<const uint8_t> jpeg, int32_t scale_denominator, uint8_t* out,
                    size_t out_bytes, size_t stride, const char* what, JpegHeader expect = {});

 private:
  Status reset_after(Status status, const char* what);
  void* handle_ = nullptr;
};

class JpegEncoder {
 public:
  // k444 keeps full colour resolution: a GelSight's surface normals are in its colours.
  enum class Subsampling : uint8_t { k420, k422, k444, kGray };

  JpegEncoder() = default;
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;
  ~JpegEncoder();

  // A baseline JPEG of `image` (RGB, or gray with kGray), quality in [1, 100]. The bytes live
  // in the encoder's buffer until the next call. The buffer has the worst-case size of the
  // largest image seen (tjBufSize; address space only: pages are touched as bytes are
  // written), so a later, larger frame never reallocates it.
  Result<std::span<const uint8_t>> encode(const ImageView& image, int32_t quality,
                                          Subsampling subsampling);
  // The worst-case size of an encoded width x height image (tjBufSize).
  static Result<size_t> max_bytes(int32_t width, int32_t height, Subsampling subsampling);

 private:
  void* handle_ = nullptr;
  unsigned char* buffer_ = nullptr;  // tjAlloc
  size_t capacity_ = 0;
};

// Conveniences for host tools (allocate; one decoder/encoder per thread behind them).
// RGB (3 channels) or gray (1) -> baseline JPEG; RGB 4:2:0, or 4:4:4 with full_chroma.
Result<std::vector<uint8_t>> encode_jpeg(const Image& image, int32_t quality,
                                         bool full_chroma = false);
// JPEG bytes -> RGB image at 1/scale_denominator. `name` (file path or "stream") in errors.
Result<Image> decode_jpeg(std::span<const uint8_t> bytes, const std::string& name,
                          int32_t scale_denominator = 1);

}  // namespace tlvlink::image
