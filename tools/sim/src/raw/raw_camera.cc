// RawCamera: processed frame -> (periphery) -> upright raw RGB -> the camera's bytes.
#include <algorithm>
#include <cstring>

#include "raw/layout.h"
#include "render/renderer_internal.h"
#include "tlvlink/image/convert.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/resample.h"
#include "tlvlink/sim/raw_camera.h"

namespace tlvlink::sim {
namespace {

using namespace internal;  // NOLINT: the raw camera's own internals

// Height-map value of the periphery the map does not cover: the lowest value validate()
// accepts, 1 m below the gel, which no press (<= 20 mm) reaches.
constexpr float kFarBelowMm = -1000.0f;

class RawCameraImpl final : public RawCamera {
 public:
  Status init(const SensorProfile& profile, uint64_t sensor_seed, const RawOptions& options);
  Status render(const ContactScene& scene, const RenderOptions& options, uint64_t noise_seed,
                RawFrame& out) override;
  Status encode_frame(std::span<const uint8_t> processed_rgb, RawFrame& out) override;
  const RawLayout& layout() const override { return layout_; }
  const SensorProfile& profile() const override { return renderer_->profile(); }

 private:
  Status render_periphery(const ContactScene& scene, const RenderOptions& options,
                          uint64_t noise_seed, const Frame& processed);
  void pad_height_map(const ContactScene& scene);
  void pad_by_repeating_edges(std::span<const uint8_t> processed_rgb);
  Status encode_source(const uint8_t* source, RawFrame& out);  // rendered size -> raw bytes
  Status encode(const uint8_t* upright, RawFrame& out);

  RawLayout layout_;
  UprightSize upright_size_;
  Periphery pad_;
  bool resize_ = false;  // false: the upright raw frame is the processed frame itself
  std::unique_ptr<Renderer> renderer_, wide_;
  ContactScene wide_scene_;
  Frame wide_frame_;
  image::Resampler resampler_;
  std::vector<uint8_t> upright_, oriented_;
  std::vector<uint8_t> padded_;  // encode_frame: the processed frame with its edges repeated
  image::JpegEncoder jpeg_;
  int32_t jpeg_quality_ = 90;
  size_t jpeg_max_bytes_ = 0;
};

Status RawCameraImpl::init(const SensorProfile& profile, uint64_t sensor_seed,
                           const RawOptions& options) {
  TLV_ASSIGN_OR_RETURN(layout_, raw_layout(profile));
  TLV_ASSIGN_OR_RETURN(renderer_, Renderer::create(profile, sensor_seed));
  upright_size_ = upright_size(layout_);
  pad_ = raw_periphery(layout_, profile);
  resize_ = layout_.crop > 0 || upright_size_.width != profile.width ||
            upright_size_.height != profile.height;
  if (layout_.crop > 0) {
    // Same sensor seed: the periphery continues this sensor's background and LED gains.
    TLV_ASSIGN_OR_RETURN(wide_, create_renderer_with_periphery(profile, sensor_seed, pad_));
  }
  const size_t upright_bytes =
      static_cast<size_t>(upright_size_.width) * static_cast<size_t>(upright_size_.height) * 3;
  if (resize_) {
    const int32_t src_w = profile.width + 2 * pad_.x, src_h = profile.height + 2 * pad_.y;
    resampler_.plan(src_w, src_h, upright_size_.width, upright_size_.height,
                    raw_from_render(layout_.crop, upright_size_.width, profile.width, pad_.x),
                    raw_from_render(layout_.crop, upright_size_.height, profile.height, pad_.y));
    upright_.assign(upright_bytes, 0);
  }
  if (layout_.format == RawFormat::kMjpeg) {
    TLV_ENSURE(options.jpeg_quality >= 1 && options.jpeg_quality <= 100,
               ErrorCode::kInvalidArgument, "raw MJPEG quality %d outside [1, 100]",
               options.jpeg_quality);
    jpeg_quality_ = options.jpeg_quality;
    TLV_ASSIGN_OR_RETURN(jpeg_max_bytes_,
                         image::JpegEncoder::max_bytes(layout_.width, layout_.height,
                                                       image::JpegEncoder::Subsampling::k422));
    if (layout_.transposed) oriented_.assign(upright_bytes, 0);
  }
  return {};
}

// The scene for the wide render: the same object at the processed render's press depth, so the
// imprint is continuous across the edge of the processed view even when the contact reaches
// past it (by force, the extra contact area in the periphery would carry load and the imprint
// would be shallower there). No JPEG round trip: the periphery is only seen through the MJPEG.
Status RawCameraImpl::render_periphery(const ContactScene& scene, const RenderOptions& options,
                                       uint64_t noise_seed, const Frame& processed) {
  wide_scene_.geometry.shape = scene.geometry.shape;
  wide_scene_.geometry.radius_mm = scene.geometry.radius_mm;
  wide_scene_.geometry.length_mm = scene.geometry.length_mm;
  wide_scene_.geometry.angle_deg = scene.geometry.angle_deg;
  wide_scene_.geometry.center_x_mm = scene.geometry.center_x_mm;
  wide_scene_.geometry.center_y_mm = scene.geometry.center_y_mm;
  if (scene.geometry.shape == Shape::kHeightMap) pad_height_map(scene);
  wide_scene_.texture = scene.texture;
  wide_scene_.mechanics = scene.mechanics;
  wide_scene_.loading = scene.loading;
  wide_scene_.loading.force_n = -1;
  // (Presses beyond the 20 mm a scene may ask for, reached only by very soft objects under
  // force control, are capped there for the periphery.)
  wide_scene_.loading.press_mm = std::clamp(processed.state.press_mm, 0.0, 20.0);
  RenderOptions wide_options = options;
  wide_options.jpeg_quality = 0;
  TLV_TRY(wide_->render(wide_scene_, wide_options, noise_seed, wide_frame_));
  // The processed frame itself in the centre: the raw frame holds exactly what
  // RawFrame::processed holds (up to the resampling and the encoding).
  const size_t row = static_cast<size_t>(processed.width) * 3;
  const size_t wide_row = static_cast<size_t>(wide_frame_.width) * 3;
  for (int32_t y = 0; y < processed.height; ++y) {
    std::memcpy(wide_frame_.rgb.data() + static_cast<size_t>(y + pad_.y) * wide_row +
                    static_cast<size_t>(pad_.x) * 3,
                processed.rgb.data() + static_cast<size_t>(y) * row, row);
  }
  return {};
}

// The map covers the processed frame; the periphery has no surface. Built in place in
// wide_scene_'s vector (its capacity survives from frame to frame).
void RawCameraImpl::pad_height_map(const ContactScene& scene) {
  const SensorProfile& p = renderer_->profile();
  const size_t w = static_cast<size_t>(p.width), h = static_cast<size_t>(p.height);
  const size_t ww = w + 2 * static_cast<size_t>(pad_.x);
  const size_t wh = h + 2 * static_cast<size_t>(pad_.y);
  auto& map = wide_scene_.geometry.height_map_mm;
  map.assign(ww * wh, kFarBelowMm);
  const auto& src = scene.geometry.height_map_mm;  // size checked: render() ran first
  for (size_t y = 0; y < h; ++y) {
    std::copy_n(src.data() + y * w, w,
                map.data() + (y + static_cast<size_t>(pad_.y)) * ww + static_cast<size_t>(pad_.x));
  }
}

Status RawCameraImpl::encode(const uint8_t* upright, RawFrame& out) {
  const UprightSize up = upright_size_;
  const std::span<const uint8_t> upright_rgb(
      upright, static_cast<size_t>(up.width) * static_cast<size_t>(up.height) * 3);
  if (layout_.format != RawFormat::kMjpeg) {
    out.bytes.resize(layout_.frame_bytes);
    return image::upright_rgb_to_camera(upright_rgb, camera_format(layout_), orientation(layout_),
                                        out.bytes);
  }
  const uint8_t* rgb = upright;
  if (layout_.transposed) {
    const image::FrameFormat oriented{image::PixelFormat::kRgb24, layout_.width, layout_.height, 0};
    TLV_TRY(image::upright_rgb_to_camera(upright_rgb, oriented, orientation(layout_), oriented_));
    rgb = oriented_.data();
  }
  TLV_ASSIGN_OR_RETURN(std::span<const uint8_t> jpeg,
                       jpeg_.encode({rgb, layout_.width, layout_.height, 3, 0}, jpeg_quality_,
                                    image::JpegEncoder::Subsampling::k422));
  // Reserve the worst case once (address space; pages are touched as bytes are written): a
  // later, larger frame never reallocates.
  if (out.bytes.capacity() < jpeg_max_bytes_) out.bytes.reserve(jpeg_max_bytes_);
  out.bytes.assign(jpeg.begin(), jpeg.end());
  return {};
}

Status RawCameraImpl::render(const ContactScene& scene, const RenderOptions& options,
                             uint64_t noise_seed, RawFrame& out) {
  TLV_TRY(renderer_->render(scene, options, noise_seed, out.processed));
  const Frame* source = &out.processed;
  if (wide_ != nullptr) {
    TLV_TRY(render_periphery(scene, options, noise_seed, out.processed));
    source = &wide_frame_;
  }
  return encode_source(source->rgb.data(), out);
}

// The processed frame at [pad, pad + size) of the padded grid, every periphery pixel a copy of
// the nearest edge pixel.
void RawCameraImpl::pad_by_repeating_edges(std::span<const uint8_t> processed_rgb) {
  const SensorProfile& p = renderer_->profile();
  const size_t w = static_cast<size_t>(p.width), h = static_cast<size_t>(p.height);
  const size_t px = static_cast<size_t>(pad_.x), py = static_cast<size_t>(pad_.y);
  const size_t ww = w + 2 * px, wh = h + 2 * py;
  padded_.resize(ww * wh * 3);
  for (size_t y = 0; y < wh; ++y) {
    const size_t sy = std::min(y >= py ? y - py : 0, h - 1);
    const uint8_t* src = processed_rgb.data() + sy * w * 3;
    uint8_t* dst = padded_.data() + y * ww * 3;
    for (size_t x = 0; x < px; ++x) std::memcpy(dst + x * 3, src, 3);
    std::memcpy(dst + px * 3, src, w * 3);
    for (size_t x = px + w; x < ww; ++x) std::memcpy(dst + x * 3, src + (w - 1) * 3, 3);
  }
}

Status RawCameraImpl::encode_frame(std::span<const uint8_t> processed_rgb, RawFrame& out) {
  const SensorProfile& p = renderer_->profile();
  const size_t expected = static_cast<size_t>(p.width) * static_cast<size_t>(p.height) * 3;
  TLV_ENSURE(processed_rgb.size() == expected, ErrorCode::kShapeMismatch,
             "%.*s raw frame: %zu bytes of processed RGB; %dx%dx3 is %zu",
             static_cast<int>(p.name.size()), p.name.data(), processed_rgb.size(), p.width,
             p.height, expected);
  if (wide_ == nullptr) return encode_source(processed_rgb.data(), out);
  pad_by_repeating_edges(processed_rgb);
  return encode_source(padded_.data(), out);
}

Status RawCameraImpl::encode_source(const uint8_t* source, RawFrame& out) {
  const uint8_t* upright = source;
  if (resize_) {
    resampler_.run(source, upright_.data());
    upright = upright_.data();
  }
  const Status encoded = encode(upright, out);
  if (!encoded.ok()) {
    const SensorProfile& p = renderer_->profile();
    return encoded.error().with_context("%.*s raw frame", static_cast<int>(p.name.size()),
                                        p.name.data());
  }
  return {};
}

}  // namespace

Result<std::unique_ptr<RawCamera>> RawCamera::create(const SensorProfile& profile,
                                                     uint64_t sensor_seed,
                                                     const RawOptions& options) {
  auto camera = std::make_unique<RawCameraImpl>();
  TLV_TRY(camera->init(profile, sensor_seed, options));
  return std::unique_ptr<RawCamera>(std::move(camera));
}

}  // namespace tlvlink::sim
