// Where things land in the raw frame: a contact appears at the right place in the camera's own
// coordinates (crop, scale, DIGIT's transpose + flip) and in the recovered frame; the Mini's
// border shows the gel's periphery; the periphery renderer continues the processed frame.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "render/renderer_internal.h"
#include "sim/render/raw_test_util.h"
#include "sim/render/render_test_util.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"

namespace tlvlink::sim {
namespace {

using testing::change_centroid;
using testing::make_camera;
using testing::make_decoder;
using testing::recover_ok;
using testing::render_raw;

// Raw image at `scale` as the camera's own orientation: MJPEG through tools/io's decoder (not
// the one under test), YUYV as its luma plane (channels = 1).
struct RawImage {
  std::vector<uint8_t> pixels;
  int32_t width = 0, height = 0, channels = 0;
};

RawImage raw_image(const RawLayout& l, const std::vector<uint8_t>& bytes, int32_t scale) {
  RawImage im;
  if (l.format == RawFormat::kYuyv) {
    im.width = l.width;
    im.height = l.height;
    im.channels = 1;
    for (size_t i = 0; i < bytes.size(); i += 2) im.pixels.push_back(bytes[i]);
    return im;
  }
  auto d = image::decode_jpeg(bytes, "raw", scale);
  EXPECT_TRUE(d.ok()) << d.error().message();
  if (!d.ok()) return im;
  im.width = d->width;
  im.height = d->height;
  im.channels = 3;
  im.pixels = std::move(d->pixels);
  return im;
}

std::vector<uint8_t> luma(const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> y(rgb.size() / 3);
  for (size_t i = 0; i < y.size(); ++i) {
    y[i] = static_cast<uint8_t>(
        std::lround(0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2]));
  }
  return y;
}

TEST(SimRenderRawGeometry, ContactAppearsWhereItShould) {
  // Measured: processed vs geometric <= 0.62 px (flat gels), recovered vs processed <= 0.21 px,
  // raw vs mapped processed <= 0.32 processed px.
  constexpr double kThresholdDn = 6;       // above JPEG ripple, below the contact's change
  constexpr double kGeometricTolPx = 1.0;  // shading is not symmetric about the ball's axis
  constexpr double kRecoveredTolPx = 0.5;  // same pixels, resampled there and back
  constexpr double kRawTolPx = 0.6;        // in processed pixels, in the raw frame
  ContactScene ball = testing::sphere(3, 3);
  ball.geometry.center_x_mm = 3;   // right of centre ...
  ball.geometry.center_y_mm = -2;  // ... and up: a transpose or a flip would move it
  ContactScene none;
  none.geometry.shape = Shape::kNone;
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    auto camera = make_camera(name);
    auto decoder = make_decoder(name);
    ASSERT_TRUE(camera && decoder);
    const SensorProfile& p = camera->profile();
    const RawLayout& l = camera->layout();
    const RawFrame touch = render_raw(*camera, ball, testing::quiet());
    const RawFrame empty = render_raw(*camera, none, testing::quiet());
    // The processed frame: at the ball's position.
    const auto pc = change_centroid(touch.processed.rgb, empty.processed.rgb, p.width, p.height, 3,
                                    kThresholdDn);
    ASSERT_GT(pc.count, 50);
    if (p.dome_sag_mm == 0) {  // a domed gel (DIGIT) meets the ball nearer its apex
      EXPECT_NEAR(pc.x, 3 / p.mm_per_px + 0.5 * p.width - 0.5, kGeometricTolPx);
      EXPECT_NEAR(pc.y, -2 / p.mm_per_px + 0.5 * p.height - 0.5, kGeometricTolPx);
    } else {
      EXPECT_GT(pc.x, 0.5 * p.width);  // still right of and above the centre
      EXPECT_LT(pc.y, 0.5 * p.height);
    }
    // The recovered frame: where the processed frame has it.
    const auto rc =
        change_centroid(recover_ok(*decoder, touch.bytes), recover_ok(*decoder, empty.bytes),
                        p.width, p.height, 3, kThresholdDn);
    EXPECT_NEAR(rc.x, pc.x, kRecoveredTolPx);
    EXPECT_NEAR(rc.y, pc.y, kRecoveredTolPx);
    // The raw frame, in the camera's coordinates: upright raw u = crop W + (x + 0.5) (1 - 2
    // crop) W / width (pixel edges at integers); DIGIT: raw (u, v) = upright (v, W - 1 - u).
    const int32_t scale = l.width > 1000 ? 8 : 1;
    const RawImage a = raw_image(l, touch.bytes, scale), b = raw_image(l, empty.bytes, scale);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    const auto c = change_centroid(a.pixels, b.pixels, a.width, a.height, a.channels,
                                   a.channels == 1 ? kThresholdDn / 3 : kThresholdDn);
    // YUYV: compare luma with luma (the coloured lights' changes partly cancel in Y, which
    // weights the imprint differently from the sum over R, G and B).
    const auto ref = a.channels == 3
                         ? pc
                         : change_centroid(luma(touch.processed.rgb), luma(empty.processed.rgb),
                                           p.width, p.height, 1, kThresholdDn / 3);
    const double up_w = l.transposed ? a.height : a.width;
    const double up_h = l.transposed ? a.width : a.height;
    const double view = 1 - 2 * l.crop;
    const double ux = l.crop * up_w + (ref.x + 0.5) * view * up_w / p.width - 0.5;
    const double uy = l.crop * up_h + (ref.y + 0.5) * view * up_h / p.height - 0.5;
    const double px_per_processed = view * up_w / p.width;
    const double tol = kRawTolPx * std::max(1.0, px_per_processed);
    if (l.transposed) {
      EXPECT_NEAR(c.x, a.width - 1 - uy, tol);
      EXPECT_NEAR(c.y, ux, tol);
    } else {
      EXPECT_NEAR(c.x, ux, tol);
      EXPECT_NEAR(c.y, uy, tol);
    }
  }
}

// The closeness bounds of raw_camera_test.cc catch a misplaced crop: decoding the Mini's frames
// as if 16 % of each border were cut (1 % of the raw frame off, 4.6 processed px at the edges)
// exceeds the quiet bound nearly 4x.
TEST(SimRenderRawGeometry, MisplacedCropExceedsTheClosenessBound) {
  constexpr double kQuietMeanAbsBound = 0.85;  // gelsight-mini's in raw_camera_test.cc
  auto camera = make_camera("gelsight-mini");
  SensorProfile wrong = sensor_profile("gelsight-mini").value();
  wrong.raw_crop = 0.16;
  auto decoder = RawDecoder::create(wrong);
  ASSERT_TRUE(camera && decoder.ok());
  RenderOptions o = testing::quiet();
  o.markers = true;
  const RawFrame raw = render_raw(*camera, testing::sphere(4), o);
  const auto c = testing::closeness(recover_ok(**decoder, raw.bytes), raw.processed.rgb);
  EXPECT_GT(c.mean_abs, kQuietMeanAbsBound);  // measured 3.18 DN (29.6 dB)
}

// The Mini's camera sees 1/0.7 of the processed field: its border is gel, not black, darker
// toward the corners (vignetting continues), and carries markers on every side.
TEST(SimRenderRawGeometry, MiniBorderShowsTheGelPeriphery) {
  auto camera = make_camera("gelsight-mini");
  ASSERT_NE(camera, nullptr);
  ContactScene none;
  none.geometry.shape = Shape::kNone;
  RenderOptions with = testing::quiet(), without = testing::quiet();
  with.markers = true;
  const RawLayout& l = camera->layout();
  const RawImage m = raw_image(l, render_raw(*camera, none, with).bytes, 8);
  const RawImage plain = raw_image(l, render_raw(*camera, none, without).bytes, 8);
  ASSERT_EQ(m.width, 410);
  ASSERT_EQ(m.height, 308);
  // The processed view at 1/8: x in [61.5, 348.5), y in [46.2, 261.8).
  auto luma = [&](const RawImage& im, int x, int y) {
    const size_t i =
        (static_cast<size_t>(y) * static_cast<size_t>(im.width) + static_cast<size_t>(x)) * 3;
    return (im.pixels[i] + im.pixels[i + 1] + im.pixels[i + 2]) / 3.0;
  };
  const double centre = luma(plain, 205, 154);
  const double edge_mid = luma(plain, 20, 154);  // left border, mid-height
  const double corner = luma(plain, 3, 3);
  EXPECT_GT(corner, 0.3 * centre);  // the gel, not the housing
  EXPECT_LT(edge_mid, centre);
  EXPECT_LT(corner, edge_mid);
  // Markers (dark dots) in each band outside the view.
  struct Band {
    const char* side;
    int x0, y0, x1, y1;
  };
  const Band bands[] = {{"left", 0, 0, 58, 308},
                        {"right", 352, 0, 410, 308},
                        {"top", 0, 0, 410, 43},
                        {"bottom", 0, 265, 410, 308}};
  for (const Band& b : bands) {
    int dark = 0;
    for (int y = b.y0; y < b.y1; ++y) {
      for (int x = b.x0; x < b.x1; ++x) dark += luma(plain, x, y) - luma(m, x, y) > 15;
    }
    EXPECT_GT(dark, 10) << b.side;
  }
}

// The periphery renderer's centre is the plain renderer's frame: same background, vignetting,
// texture statistics and markers (no seam at the edge of the processed view in a raw frame).
TEST(SimRenderRawGeometry, PeripheryRendererContinuesTheProcessedFrame) {
  const SensorProfile p = sensor_profile("gelsight-mini").value();
  auto plain = Renderer::create(p, 3);
  auto wide = internal::create_renderer_with_periphery(p, 3, {71, 54});
  ASSERT_TRUE(plain.ok() && wide.ok());
  ContactScene none;
  none.geometry.shape = Shape::kNone;
  ContactScene ball = testing::sphere(0, 4);  // by press depth: the same imprint in both
  ball.loading.force_n = -1;
  ball.loading.press_mm = 0.4;
  ball.texture.sq_um = 20;
  ContactScene plate = ball;  // reaches past the view: texture statistics over the view only
  plate.geometry.shape = Shape::kFlatPlate;
  plate.loading.press_mm = 0.05;
  RenderOptions o = testing::quiet();
  o.markers = true;
  for (const ContactScene* s : {&none, &ball, &plate}) {
    const Frame a = testing::render_ok(**plain, *s, o);
    const Frame b = testing::render_ok(**wide, *s, o);
    ASSERT_EQ(b.width, p.width + 142);
    ASSERT_EQ(b.height, p.height + 108);
    int max_diff = 0;
    double sum = 0;
    for (int y = 0; y < p.height; ++y) {
      for (int x = 0; x < p.width * 3; ++x) {
        const int d = std::abs(a.rgb[static_cast<size_t>(y * p.width * 3 + x)] -
                               b.rgb[static_cast<size_t>((y + 54) * b.width * 3 + 71 * 3 + x)]);
        max_diff = std::max(max_diff, d);
        sum += d;
      }
    }
    // Background and a central imprint: identical but for float rounding (1 DN). A plate that
    // fills the view: the membrane blur near the view's edge sees the imprint continue instead
    // of a repeated edge (measured max 5 DN, mean 0.03 DN).
    const bool fills_view = s->geometry.shape == Shape::kFlatPlate;
    EXPECT_LE(max_diff, fills_view ? 8 : 1) << static_cast<int>(s->geometry.shape);
    EXPECT_LE(sum / (p.width * p.height * 3), fills_view ? 0.1 : 0.01);
  }
}

}  // namespace
}  // namespace tlvlink::sim
