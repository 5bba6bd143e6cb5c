// RawDecoder: the camera's bytes -> the processed frame, through the runtime's FrameDecoder
// (runtime/image), exactly as the board's capture pipeline decodes a real camera's frames.
#include <string>

#include "raw/layout.h"
#include "tlvlink/image/frame_decoder.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim {
namespace {

class RawDecoderImpl final : public RawDecoder {
 public:
  Status init(const SensorProfile& profile, const RecoverOptions& options) {
    TLV_ASSIGN_OR_RETURN(layout_, raw_layout(profile));
    const int32_t d = options.jpeg_scale_denominator;
    TLV_ENSURE(d == 0 || d == 1 || d == 2 || d == 4 || d == 8, ErrorCode::kInvalidArgument,
               "recover: jpeg_scale_denominator %d (0 = auto, 1, 2, 4 or 8)", d);
    what_ = std::string(profile.name) + " raw frame";
    image::SensorView view;
    view.width = profile.width;
    view.height = profile.height;
    view.crop = layout_.crop;
    view.orientation = internal::orientation(layout_);
    view.jpeg_scale_denominator = d;
    TLV_ASSIGN_OR_RETURN(decoder_,
                         image::FrameDecoder::create(internal::camera_format(layout_), view));
    return {};
  }

  Status recover(std::span<const uint8_t> raw, std::vector<uint8_t>& rgb) override {
    // A simulated camera's uncompressed frames have exactly their size (a real camera's may be
    // padded; the FrameDecoder accepts those).
    TLV_ENSURE(layout_.format == RawFormat::kMjpeg || raw.size() == layout_.frame_bytes,
               ErrorCode::kFormat, "%s: %zu bytes; %dx%d %s is %zu bytes", what_.c_str(),
               raw.size(), layout_.width, layout_.height,
               layout_.format == RawFormat::kYuyv ? "YUYV (2 bytes/pixel)" : "RGB",
               layout_.frame_bytes);
    rgb.resize(decoder_.output_bytes());
    return decoder_.decode(raw, rgb, what_.c_str());
  }

  const RawLayout& layout() const override { return layout_; }
  int32_t jpeg_scale_denominator() const override { return decoder_.jpeg_scale_denominator(); }

 private:
  std::string what_;  // "<profile> raw frame", for errors
  RawLayout layout_;
  image::FrameDecoder decoder_;
};

}  // namespace

Result<std::unique_ptr<RawDecoder>> RawDecoder::create(const SensorProfile& profile,
                                                       const RecoverOptions& options) {
  auto decoder = std::make_unique<RawDecoderImpl>();
  TLV_TRY(decoder->init(profile, options));
  return std::unique_ptr<RawDecoder>(std::move(decoder));
}

}  // namespace tlvlink::sim
