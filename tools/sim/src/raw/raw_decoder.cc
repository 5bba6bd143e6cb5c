// RawDecoder: the camera's bytes -> upright raw RGB (decoded, possibly DCT-scaled) -> cropped
// and resized to the processed frame, as a capture pipeline does.
#include <cstring>
#include <string>

#include "raw/layout.h"
#include "raw/mjpeg.h"
#include "raw/pixel_formats.h"
#include "raw/resample.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim {
namespace {

using namespace internal;  // NOLINT: the raw camera's own internals

// Auto scale: the cropped view must keep this share of the processed size on each axis. The
// Mini's 1/8 decode keeps 90 % (287 x 216 px for 320 x 240) and costs a fraction of 1/4's; an
// 80 % floor still refuses a scale that would lose more than a fifth of the resolution.
constexpr double kMinViewShare = 0.8;

class RawDecoderImpl final : public RawDecoder {
 public:
  Status init(const SensorProfile& profile, const RecoverOptions& options);
  Status recover(std::span<const uint8_t> raw, std::vector<uint8_t>& rgb) override;
  const RawLayout& layout() const override { return layout_; }
  int32_t jpeg_scale_denominator() const override { return scale_; }

 private:
  int32_t choose_scale(const SensorProfile& profile) const;

  std::string what_;  // "<profile> raw frame", for errors
  RawLayout layout_;
  RawLayout decoded_;  // the layout at the decode scale (MJPEG) or layout_
  int32_t width_ = 0, height_ = 0;
  int32_t scale_ = 1;
  bool resize_ = false;
  MjpegDecoder jpeg_;
  std::vector<uint8_t> upright_;
  Resampler resampler_;
};

int32_t RawDecoderImpl::choose_scale(const SensorProfile& p) const {
  for (int32_t d : {8, 4, 2}) {
    RawLayout scaled = layout_;
    scaled.width = jpeg_scaled_size(layout_.width, d);
    scaled.height = jpeg_scaled_size(layout_.height, d);
    const UprightSize up = upright_size(scaled);
    const double view = 1 - 2 * layout_.crop;
    if (view * up.width >= kMinViewShare * p.width && view * up.height >= kMinViewShare * p.height)
      return d;
  }
  return 1;
}

Status RawDecoderImpl::init(const SensorProfile& profile, const RecoverOptions& options) {
  TLV_ASSIGN_OR_RETURN(layout_, raw_layout(profile));
  const int32_t d = options.jpeg_scale_denominator;
  TLV_ENSURE(d == 0 || d == 1 || d == 2 || d == 4 || d == 8, ErrorCode::kInvalidArgument,
             "recover: jpeg_scale_denominator %d (0 = auto, 1, 2, 4 or 8)", d);
  what_ = std::string(profile.name) + " raw frame";
  width_ = profile.width;
  height_ = profile.height;
  decoded_ = layout_;
  if (layout_.format == RawFormat::kMjpeg) {
    scale_ = d != 0 ? d : choose_scale(profile);
    TLV_TRY(jpeg_.init(layout_.width, layout_.height, scale_));
    decoded_.width = jpeg_.scaled_width();
    decoded_.height = jpeg_.scaled_height();
  }
  const UprightSize up = upright_size(decoded_);
  upright_.assign(static_cast<size_t>(up.width) * static_cast<size_t>(up.height) * 3, 0);
  resize_ = layout_.crop > 0 || up.width != width_ || up.height != height_;
  if (resize_) {
    resampler_.plan(up.width, up.height, width_, height_,
                    processed_from_raw(layout_.crop, up.width, width_),
                    processed_from_raw(layout_.crop, up.height, height_));
  }
  return {};
}

Status RawDecoderImpl::recover(std::span<const uint8_t> raw, std::vector<uint8_t>& rgb) {
  const uint8_t* upright = upright_.data();
  switch (layout_.format) {
    case RawFormat::kRgb:
    case RawFormat::kYuyv: {
      const bool yuyv = layout_.format == RawFormat::kYuyv;
      TLV_ENSURE(raw.size() == layout_.frame_bytes, ErrorCode::kFormat,
                 "%s: %zu bytes; %dx%d %s is %zu bytes", what_.c_str(), raw.size(), layout_.width,
                 layout_.height, yuyv ? "YUYV (2 bytes/pixel)" : "RGB", layout_.frame_bytes);
      if (yuyv) {
        yuyv_to_upright(raw.data(), layout_, upright_.data());
      } else if (layout_.transposed) {
        raw_rgb_to_upright(raw.data(), layout_, upright_.data());
      } else {
        upright = raw.data();
      }
      break;
    }
    case RawFormat::kMjpeg:
      TLV_TRY(jpeg_.decode(raw, what_.c_str()));
      if (layout_.transposed) {
        raw_rgb_to_upright(jpeg_.pixels(), decoded_, upright_.data());
      } else {
        upright = jpeg_.pixels();
      }
      break;
  }
  rgb.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  if (resize_) {
    resampler_.run(upright, rgb.data());
  } else {
    std::memcpy(rgb.data(), upright, rgb.size());
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<RawDecoder>> RawDecoder::create(const SensorProfile& profile,
                                                       const RecoverOptions& options) {
  auto decoder = std::make_unique<RawDecoderImpl>();
  TLV_TRY(decoder->init(profile, options));
  return std::unique_ptr<RawDecoder>(std::move(decoder));
}

}  // namespace tlvlink::sim
