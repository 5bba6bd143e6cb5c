#pragma once
// The simulated sensor's raw camera output: a scene rendered as the bytes the physical camera
// emits (the Mini's MJPEG 3280x2464, DIGIT's YUYV in its own orientation, the R1.5's MJPEG
// 320x240), and the inverse a capture pipeline applies: raw bytes -> the processed RGB frame.
// Geometry and formats: tools/sim/REFERENCE.md, "Raw camera output".
//
// Both classes own their buffers: after the first frame, RawCamera::render and
// RawDecoder::recover make no allocation of their own (libjpeg-turbo still mallocs its
// per-image working memory inside each compress/decompress call). One object per thread.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/sim/renderer.h"
#include "tlvlink/sim/sensor.h"

namespace tlvlink::sim {

enum class RawFormat : uint8_t {
  kRgb,    // interleaved 8-bit RGB, width * height * 3 bytes
  kMjpeg,  // one baseline JPEG per frame (4:2:2), size varies
  kYuyv,   // YUYV 4:2:2 (Y0 U Y1 V per pixel pair), BT.601 limited range, width * height * 2
};

// Where the processed frame lies in the raw one, derived from the profile's raw_* fields.
struct RawLayout {
  RawFormat format = RawFormat::kRgb;
  int32_t width = 0, height = 0;  // the raw frame as the camera emits it (its orientation)
  double crop = 0;                // fraction of each raw border outside the processed view
  bool transposed = false;        // processed = flip_top_bottom(transpose(raw))
  // Bytes of every frame for kRgb and kYuyv; 0 for kMjpeg (the size varies per frame).
  size_t frame_bytes = 0;
};

// Checks the raw fields against the processed frame: the cropped raw view (transposed when
// raw_transposed) must have the processed aspect ratio within 2 %, and YUYV needs an even width.
Result<RawLayout> raw_layout(const SensorProfile& profile);
const char* raw_format_name(RawFormat format);  // "rgb", "mjpeg", "yuyv"

struct RawOptions {
  int32_t jpeg_quality = 90;  // [1, 100], the MJPEG encoder's quality
};

struct RawFrame {
  std::vector<uint8_t> bytes;  // the frame as the device emits it; capacity reused
  // The processed frame rendered from the same (scene, options, noise_seed): what a pipeline
  // should recover from `bytes`, and identical to Renderer::render's frame.
  Frame processed;
};

class RawCamera {
 public:
  // Validates the profile, options and raw layout; allocates the renderers and buffers.
  static Result<std::unique_ptr<RawCamera>> create(const SensorProfile& profile,
                                                   uint64_t sensor_seed,
                                                   const RawOptions& options = {});
  virtual ~RawCamera() = default;

  // Renders the scene as the camera's raw output. With raw_crop > 0 the camera's whole field is
  // drawn: the processed frame in the centre, the gel's periphery (background, vignetting,
  // markers, the contact where it reaches) around it, then resized to the raw size.
  virtual Status render(const ContactScene& scene, const RenderOptions& options,
                        uint64_t noise_seed, RawFrame& out) = 0;

  // An already rendered processed frame (profile height * width * 3 RGB) as the camera's raw
  // bytes, in out.bytes (out.processed is left alone). The periphery beyond the processed view,
  // which render() draws, is the frame's edge pixels repeated: RawDecoder crops it away, so only
  // the resampler's taps and the JPEG blocks at the crop line see the difference.
  virtual Status encode_frame(std::span<const uint8_t> processed_rgb, RawFrame& out) = 0;

  virtual const RawLayout& layout() const = 0;
  virtual const SensorProfile& profile() const = 0;
};

struct RecoverOptions {
  // MJPEG only: decode at 1/1, 1/2, 1/4 or 1/8 size (libjpeg-turbo scales in the DCT). 0 =
  // the smallest scale whose cropped view still has at least 80 % of the processed size on
  // each axis (1/8 for the Mini, 1/1 for the R1.5).
  int32_t jpeg_scale_denominator = 0;
};

class RawDecoder {
 public:
  static Result<std::unique_ptr<RawDecoder>> create(const SensorProfile& profile,
                                                    const RecoverOptions& options = {});
  virtual ~RawDecoder() = default;

  // Raw bytes of this profile -> the processed frame: height * width * 3 RGB in `rgb` (resized,
  // capacity reused). A frame of the wrong size or format, or a truncated or corrupt JPEG, is a
  // kFormat error that says what was expected.
  virtual Status recover(std::span<const uint8_t> raw, std::vector<uint8_t>& rgb) = 0;

  virtual const RawLayout& layout() const = 0;
  virtual int32_t jpeg_scale_denominator() const = 0;  // the scale in use (1 unless MJPEG)
};

}  // namespace tlvlink::sim
