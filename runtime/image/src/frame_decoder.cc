#include <algorithm>
#include <cmath>
#include <cstring>

#include "jpeg_region.h"
#include "tlvlink/image/frame_decoder.h"

namespace tlvlink::image {
namespace {

int32_t choose_scale(const FrameFormat& camera, const SensorView& v) {
  for (int32_t d : {8, 4, 2}) {
    const Size up = upright_size(jpeg_scaled_size(camera.width, d),
                                 jpeg_scaled_size(camera.height, d), v.orientation);
    const double share = 1 - 2 * v.crop;
    if (share * up.width >= kMinViewShare * v.width &&
        share * up.height >= kMinViewShare * v.height) {
      return d;
    }
  }
  return 1;
}

// The scaled region a cropped view reads: the view and a margin for the resampler's support.
constexpr int32_t kRegionMargin = 2;

internal::Region view_region(int32_t w, int32_t h, double crop) {
  const auto lo = [&](int32_t len) {
    return std::max(0, static_cast<int32_t>(std::floor(crop * len)) - kRegionMargin);
  };
  const auto hi = [&](int32_t len) {
    return std::min(len, static_cast<int32_t>(std::ceil((1 - crop) * len)) + kRegionMargin);
  };
  return {lo(w), lo(h), hi(w) - lo(w), hi(h) - lo(h)};
}

}  // namespace

FrameDecoder::FrameDecoder() = default;
FrameDecoder::FrameDecoder(FrameDecoder&&) noexcept = default;
FrameDecoder& FrameDecoder::operator=(FrameDecoder&&) noexcept = default;
FrameDecoder::~FrameDecoder() = default;

Result<FrameDecoder> FrameDecoder::create(const FrameFormat& camera, const SensorView& view) {
  TLV_ENSURE(camera.width >= 1 && camera.height >= 1 && view.width >= 1 && view.height >= 1,
             ErrorCode::kInvalidArgument, "frame decoder: camera %dx%d, view %dx%d", camera.width,
             camera.height, view.width, view.height);
  TLV_ENSURE(view.crop >= 0 && view.crop < 0.5, ErrorCode::kInvalidArgument,
             "frame decoder: crop %.3f outside [0, 0.5)", view.crop);
  const int32_t d = view.jpeg_scale_denominator;
  TLV_ENSURE(d == 0 || jpeg_scale_supported(d), ErrorCode::kInvalidArgument,
             "frame decoder: jpeg_scale_denominator %d (0 = auto, 1, 2, 4 or 8)", d);
  FrameDecoder f;
  f.camera_ = camera;
  f.view_ = view;
  f.decoded_ = camera;
  if (camera.format == PixelFormat::kMjpeg) {
    f.scale_ = d != 0 ? d : choose_scale(camera, view);
    f.decoded_ = {PixelFormat::kRgb24, jpeg_scaled_size(camera.width, f.scale_),
                  jpeg_scaled_size(camera.height, f.scale_), 0};
    if (view.crop > 0 && view.orientation == Orientation::kUpright) {
      f.region_ = std::make_unique<internal::JpegRegionDecoder>();
      TLV_TRY(f.region_->init(camera.width, camera.height, f.scale_,
                              view_region(f.decoded_.width, f.decoded_.height, view.crop)));
    } else {
      f.decoded_rgb_.assign(frame_bytes(f.decoded_), 0);
    }
  }
  const Size up = upright_size(f.decoded_.width, f.decoded_.height, view.orientation);
  const double camera_aspect = static_cast<double>(up.width) / static_cast<double>(up.height);
  const double view_aspect = static_cast<double>(view.width) / static_cast<double>(view.height);
  TLV_ENSURE(std::abs(camera_aspect / view_aspect - 1.0) <= kMaxViewAspectChange,
             ErrorCode::kShapeMismatch,
             "frame decoder: a %dx%d camera frame (%dx%d upright, aspect %.3f) cannot become the "
             "%dx%d view (aspect %.3f) without stretching the gel (tolerance %.0f %%): configure "
             "the sensor model that produces these frames, or crop them to the view's aspect",
             camera.width, camera.height, up.width, up.height, camera_aspect, view.width,
             view.height, view_aspect, 100 * kMaxViewAspectChange);
  f.upright_.assign(static_cast<size_t>(up.width) * static_cast<size_t>(up.height) * 3, 0);
  f.resize_ = view.crop > 0 || up.width != view.width || up.height != view.height;
  if (f.resize_) {
    f.resampler_.plan(up.width, up.height, view.width, view.height,
                      view_from_camera(view.crop, up.width, view.width),
                      view_from_camera(view.crop, up.height, view.height));
  }
  return f;
}

size_t FrameDecoder::output_bytes() const {
  return static_cast<size_t>(view_.width) * static_cast<size_t>(view_.height) * 3;
}

Status FrameDecoder::decode(std::span<const uint8_t> frame, std::span<uint8_t> out,
                            const char* what) {
  TLV_ENSURE(out.size() == output_bytes(), ErrorCode::kShapeMismatch,
             "%s: output of %zu bytes for a %dx%d RGB frame", what, out.size(), view_.width,
             view_.height);
  const uint8_t* upright = upright_.data();
  if (region_ != nullptr) {
    TLV_TRY(region_->decode(frame, what));
    const internal::Region& r = region_->got();
    if (r.x != planned_region_x_) {
      // The resampler reads the region: the view's axis maps shifted by its origin. Planned on
      // the first frame (the region's start depends on the stream's subsampling).
      AxisMap x = view_from_camera(view_.crop, decoded_.width, view_.width);
      AxisMap y = view_from_camera(view_.crop, decoded_.height, view_.height);
      x.offset -= r.x;
      y.offset -= r.y;
      resampler_.plan(r.width, r.height, view_.width, view_.height, x, y);
      planned_region_x_ = r.x;
    }
    resampler_.run_strided(region_->pixels(), region_->row_bytes(), out.data());
    return {};
  }
  if (camera_.format == PixelFormat::kMjpeg) {
    TLV_TRY(jpeg_.decode_rgb(frame, scale_, decoded_rgb_.data(), decoded_rgb_.size(), 0, what,
                             {camera_.width, camera_.height}));
    if (view_.orientation == Orientation::kUpright) {
      upright = decoded_rgb_.data();
    } else {
      TLV_TRY(camera_to_upright_rgb(decoded_rgb_, decoded_, view_.orientation, upright_, what));
    }
  } else if (camera_.format == PixelFormat::kRgb24 && view_.orientation == Orientation::kUpright &&
             (camera_.stride == 0 || camera_.stride == camera_.width * 3)) {
    TLV_ENSURE(frame.size() >= frame_bytes(camera_), ErrorCode::kFormat,
               "%s: %zu bytes; %dx%d rgb24 is %zu bytes", what, frame.size(), camera_.width,
               camera_.height, frame_bytes(camera_));
    upright = frame.data();  // already what the resampler reads
  } else {
    TLV_TRY(camera_to_upright_rgb(frame, camera_, view_.orientation, upright_, what));
  }
  if (resize_) {
    resampler_.run(upright, out.data());
  } else {
    std::memcpy(out.data(), upright, out.size());
  }
  return {};
}

}  // namespace tlvlink::image
