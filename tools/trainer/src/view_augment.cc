// The sensor-view augmentation chain: draws, then mounting -> optics -> focus -> noise ->
// codec -> the model's resize. The ranges are the README's table ("Sensor-view augmentation");
// where a range comes from, it says so.

#include "view_augment.h"

#include <cmath>
#include <cstring>
#include <memory>

#include "augment_rng.h"
#include "tlvlink/image/convert.h"
#include "view_optics.h"

namespace tlvlink::trainer {
namespace {

using rng::chance;
using rng::normal;
using rng::uniform;

constexpr double kPi = 3.14159265358979323846;

// Probability that a view draws each component (when the options enable it).
constexpr double kPGeometry = 0.6, kPColour = 0.8, kPVignette = 0.4, kPLedDrift = 0.4,
                 kPDust = 0.25, kPBlur = 0.5, kPNoise = 0.6, kPCodec = 0.75;

struct Named {
  ViewComponent bit;
  const char* name;
};
constexpr Named kNames[] = {{kViewGeometry, "geometry"}, {kViewColour, "colour"},
                            {kViewVignette, "vignette"}, {kViewLedDrift, "led-drift"},
                            {kViewDust, "dust"},         {kViewBlur, "blur"},
                            {kViewNoise, "noise"},       {kViewCodec, "codec"}};

}  // namespace

std::string view_components_name(uint32_t components) {
  if (components == 0) return "none";
  if ((components & kViewAll) == kViewAll) return "all";
  std::string s;
  for (const Named& n : kNames) {
    if (components & n.bit) s += (s.empty() ? "" : ",") + std::string(n.name);
  }
  return s;
}

Result<uint32_t> parse_view_components(std::string_view list) {
  if (list == "all") return static_cast<uint32_t>(kViewAll);
  if (list == "none" || list.empty()) return 0u;
  uint32_t bits = 0;
  while (!list.empty()) {
    const size_t comma = list.find(',');
    const std::string_view item = list.substr(0, comma);
    bool known = false;
    for (const Named& n : kNames) {
      if (item == n.name) {
        bits |= n.bit;
        known = true;
      }
    }
    TLV_ENSURE(known, ErrorCode::kInvalidArgument,
               "unknown view augmentation '%.*s' (known: all, none, geometry, colour, vignette, "
               "led-drift, dust, blur, noise, codec)",
               static_cast<int>(item.size()), item.data());
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return bits;
}

uint64_t view_seed(uint64_t run_seed, int64_t step, int64_t index, int32_t view) {
  uint64_t s = run_seed ^ 0x243f6a8885a308d3ull;
  s ^= rng::splitmix(s) + static_cast<uint64_t>(step) * 0x9e3779b97f4a7c15ull;
  s ^= rng::splitmix(s) + static_cast<uint64_t>(index) * 0xd1b54a32d192ed03ull;
  s ^= rng::splitmix(s) + static_cast<uint64_t>(view) * 0x94d049bb133111ebull;
  return rng::splitmix(s);
}

Result<ViewAugmenter> ViewAugmenter::create(int32_t frame_width, int32_t frame_height,
                                            const InputSpec& spec, image::Orientation camera) {
  TLV_ENSURE(
      frame_width >= 16 && frame_height >= 16 && frame_width % 2 == 0 && frame_height % 2 == 0,
      ErrorCode::kInvalidArgument,
      "view augmentation frame %dx%d: sides >= 16 and even (YUYV pairs)", frame_width,
      frame_height);
  TLV_ENSURE(spec.crop_w == 0, ErrorCode::kInvalidArgument,
             "view augmentation: the model input crops; the views are made of the whole frame");
  ViewAugmenter a;
  TLV_ASSIGN_OR_RETURN(a.resize_,
                       image::PreprocessPlan::create(spec, frame_width, frame_height, 3));
  a.width_ = frame_width;
  a.height_ = frame_height;
  a.camera_ = camera;
  const size_t n = static_cast<size_t>(frame_width) * static_cast<size_t>(frame_height) * 3;
  a.work_.resize(n);
  a.tmp_.resize(n);
  a.frame8_.resize(n);
  a.codec8_.resize(n);
  a.big8_.resize(n * 16);
  const image::AxisMap x2{0, 0.5}, x4{0, 0.25};
  a.up2_.plan(frame_width, frame_height, frame_width * 2, frame_height * 2, x2, x2);
  a.up4_.plan(frame_width, frame_height, frame_width * 4, frame_height * 4, x4, x4);
  a.encoder_ = std::make_unique<image::JpegEncoder>();
  a.decoder_ = std::make_unique<image::JpegDecoder>();
  return a;
}

Status ViewAugmenter::codec(uint64_t& state, ViewDraw& draw) {
  const image::ImageView frame{frame8_.data(), width_, height_, 3, 0};
  const double kind = rng::uniform01(state);
  if (kind < 0.45) {
    // A stored or re-saved frame: any quality a tool or dataset may use.
    draw.codec = ViewDraw::Codec::kJpeg;
    draw.quality = rng::uniform_int(state, 50, 98);
    const auto sub = chance(state, 0.7) ? image::JpegEncoder::Subsampling::k420
                                        : image::JpegEncoder::Subsampling::k422;
    TLV_ASSIGN_OR_RETURN(auto bytes, encoder_->encode(frame, draw.quality, sub));
    return decoder_->decode_rgb(bytes, 1, codec8_.data(), codec8_.size(), 0, "view augmentation");
  }
  if (kind < 0.8) {
    // An MJPEG camera decoded with DCT scaling (the board's path for a GelSight Mini): the
    // camera sees the gel at k times the processed resolution, encodes 4:2:2 at a camera's
    // quality, and the decoder's IDCT shrinks it back.
    draw.codec = ViewDraw::Codec::kMjpegScaled;
    draw.dct_scale = chance(state, 0.85) ? 2 : 4;
    draw.quality = rng::uniform_int(state, 75, 95);
    const int32_t k = draw.dct_scale;
    (k == 2 ? up2_ : up4_).run(frame8_.data(), big8_.data());
    const image::ImageView big{big8_.data(), width_ * k, height_ * k, 3, 0};
    TLV_ASSIGN_OR_RETURN(
        auto bytes, encoder_->encode(big, draw.quality, image::JpegEncoder::Subsampling::k422));
    return decoder_->decode_rgb(bytes, k, codec8_.data(), codec8_.size(), 0, "view augmentation");
  }
  // A UVC camera's YUYV (DIGIT): BT.601 limited range, chroma shared by each pixel pair of the
  // camera's own rows.
  draw.codec = ViewDraw::Codec::kYuyv;
  const bool turned = camera_ == image::Orientation::kTransposed;
  const image::FrameFormat yuyv{image::PixelFormat::kYuyv, turned ? height_ : width_,
                                turned ? width_ : height_, 0};
  std::span<uint8_t> packed(big8_.data(), image::frame_bytes(yuyv));
  TLV_TRY(image::upright_rgb_to_camera(frame8_, yuyv, camera_, packed));
  return image::camera_to_upright_rgb(packed, yuyv, camera_, codec8_, "view augmentation");
}

Status ViewAugmenter::make(std::span<const uint8_t> frame, uint32_t components, uint64_t seed,
                           std::span<uint8_t> out, ViewDraw* draw) {
  return make_view(frame, components, seed, nullptr, out, draw);
}

Status ViewAugmenter::make_codec_twin(std::span<const uint8_t> frame, uint32_t components,
                                      uint64_t seed, uint64_t codec_seed, std::span<uint8_t> out,
                                      ViewDraw* draw) {
  return make_view(frame, components, seed, &codec_seed, out, draw);
}

Status ViewAugmenter::make_view(std::span<const uint8_t> frame, uint32_t components, uint64_t seed,
                                const uint64_t* twin_codec_seed, std::span<uint8_t> out,
                                ViewDraw* draw_out) {
  const size_t n = work_.size();
  TLV_ENSURE(frame.size() == n, ErrorCode::kShapeMismatch,
             "view augmentation: frame of %zu bytes, expected %dx%dx3", frame.size(), width_,
             height_);
  uint64_t state = seed;
  ViewDraw draw;
  const auto on = [&](ViewComponent c, double p) {
    // Always draw, so one component's setting does not move another's random stream.
    const bool drawn = chance(state, p);
    if ((components & c) && drawn) draw.applied |= c;
    return (components & c) && drawn;
  };
  for (size_t i = 0; i < n; ++i) work_[i] = frame[i];
  const int32_t w = width_, h = height_;

  view::Affine mount;
  mount.scale = uniform(state, 0.95, 1.05);
  mount.rotation_rad = uniform(state, -3.0, 3.0) * kPi / 180;
  mount.shift_x = uniform(state, -0.03, 0.03) * w;
  mount.shift_y = uniform(state, -0.03, 0.03) * h;
  if (on(kViewGeometry, kPGeometry)) {
    view::warp(work_.data(), tmp_.data(), w, h, mount);
    work_.swap(tmp_);
  }

  view::Shading shading;
  bool shaded = false;
  const double exposure = std::exp(0.12 * normal(state));
  float gain[3], offset[3], drift[3];
  for (int c = 0; c < 3; ++c) {
    gain[c] = static_cast<float>(exposure * std::exp(0.10 * normal(state)));
    offset[c] = static_cast<float>(5.0 * normal(state));
    drift[c] = static_cast<float>(uniform(state, -0.12, 0.12));
  }
  if (on(kViewColour, kPColour)) {
    std::memcpy(shading.gain, gain, sizeof(gain));
    std::memcpy(shading.offset, offset, sizeof(offset));
    shaded = true;
  }
  const double vignette = uniform(state, 0.0, 0.3);
  const double vcx = uniform(state, 0.4, 0.6), vcy = uniform(state, 0.4, 0.6);
  if (on(kViewVignette, kPVignette)) {
    shading.vignette = vignette;
    shading.vignette_cx = vcx;
    shading.vignette_cy = vcy;
    shaded = true;
  }
  const double drift_angle = uniform(state, 0, 2 * kPi);
  if (on(kViewLedDrift, kPLedDrift)) {
    std::memcpy(shading.drift, drift, sizeof(drift));
    shading.drift_angle_rad = drift_angle;
    shaded = true;
  }
  if (shaded) view::shade(work_.data(), w, h, shading);

  view::Speck specks[5];
  const int32_t count = rng::uniform_int(state, 1, 5);
  for (view::Speck& s : specks) {
    s = {uniform(state, 0, w), uniform(state, 0, h), uniform(state, 0.8, 3.0),
         uniform(state, 0.15, 0.6)};
  }
  if (on(kViewDust, kPDust)) {
    for (int32_t i = 0; i < count; ++i) view::darken(work_.data(), w, h, specks[i]);
  }

  const double sigma = uniform(state, 0.3, 1.4);
  if (on(kViewBlur, kPBlur)) {
    draw.blur_sigma = sigma;
    view::blur(work_.data(), w, h, sigma, tmp_);
  }
  const double noise = uniform(state, 0.5, 3.0);
  const uint64_t noise_seed = rng::splitmix(state);
  if (on(kViewNoise, kPNoise)) {
    draw.noise_dn = noise;
    view::add_noise(work_.data(), n, noise, noise_seed);
  }
  view::to_uint8(work_.data(), frame8_.data(), n);

  const uint64_t codec_seed = rng::splitmix(state);
  const uint8_t* final_frame = frame8_.data();
  bool coded = on(kViewCodec, kPCodec);
  uint64_t codec_state = codec_seed;
  if (twin_codec_seed != nullptr) {
    // The twin draws the codec afresh; everything before it is the original's.
    codec_state = *twin_codec_seed;
    coded = (components & kViewCodec) && chance(codec_state, kPCodec);
    if (coded) {
      draw.applied |= kViewCodec;
    } else {
      draw.applied &= ~static_cast<uint32_t>(kViewCodec);
    }
    codec_state = rng::splitmix(codec_state);
  }
  if (coded) {
    TLV_TRY(codec(codec_state, draw));
    final_frame = codec8_.data();
  }
  if (draw_out != nullptr) *draw_out = draw;
  return resize_.resize({final_frame, w, h, 3, 0}, out);
}

}  // namespace tlvlink::trainer
