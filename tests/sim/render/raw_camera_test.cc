// The raw camera: each profile's frames have exactly the size and format its profile records,
// the processed frame that travels with them is the renderer's, and the frame a pipeline
// recovers from the bytes is close to it (JPEG + resampling only).
#include "tlvlink/sim/raw_camera.h"  // first: the public header compiles on its own

#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/raw_test_util.h"
#include "sim/render/render_test_util.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"
#include "tlvlink/sim/extreme.h"

namespace tlvlink::sim {
namespace {

using testing::closeness;
using testing::make_camera;
using testing::make_decoder;
using testing::recover_ok;
using testing::render_raw;
using testing::sphere;

RenderOptions with_markers() {
  RenderOptions o;
  o.markers = true;
  return o;
}

TEST(SimRenderRaw, EveryProfileEmitsItsRecordedSizeAndFormat) {
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    const SensorProfile p = sensor_profile(name).value();
    auto camera = make_camera(name);
    ASSERT_NE(camera, nullptr);
    const RawLayout& l = camera->layout();
    EXPECT_EQ(l.width, p.raw_width);
    EXPECT_EQ(l.height, p.raw_height);
    EXPECT_EQ(raw_format_name(l.format), p.raw_format);
    const RawFrame f = render_raw(*camera, sphere(4), with_markers());
    EXPECT_EQ(f.processed.width, p.width);
    EXPECT_EQ(f.processed.height, p.height);
    if (l.format == RawFormat::kYuyv) {
      // Two bytes per pixel: 320x240 -> 153,600 bytes, 640x480 -> 614,400.
      EXPECT_EQ(f.bytes.size(), static_cast<size_t>(p.raw_width) * p.raw_height * 2);
      EXPECT_EQ(l.frame_bytes, f.bytes.size());
      // Limited range: Y in [16, 235], Cb and Cr in [16, 240].
      for (size_t i = 0; i < f.bytes.size(); ++i) {
        ASSERT_GE(f.bytes[i], 16) << i;
        ASSERT_LE(f.bytes[i], i % 2 == 0 ? 235 : 240) << i;
      }
    } else {
      ASSERT_EQ(l.format, RawFormat::kMjpeg);
      EXPECT_EQ(l.frame_bytes, 0u);
      ASSERT_GE(f.bytes.size(), 4u);
      EXPECT_EQ(f.bytes[0], 0xFF);  // SOI ... EOI: one complete JPEG per frame
      EXPECT_EQ(f.bytes[1], 0xD8);
      EXPECT_EQ(f.bytes[f.bytes.size() - 2], 0xFF);
      EXPECT_EQ(f.bytes[f.bytes.size() - 1], 0xD9);
      // An independent decoder (tools/io) sees the camera's size.
      auto decoded = image::decode_jpeg(f.bytes, std::string(name), 8);
      ASSERT_TRUE(decoded.ok()) << decoded.error().message();
      auto header = image::decode_jpeg(f.bytes, std::string(name), 1);
      ASSERT_TRUE(header.ok());
      EXPECT_EQ(header->width, p.raw_width);
      EXPECT_EQ(header->height, p.raw_height);
    }
  }
}

TEST(SimRenderRaw, ProcessedFrameIsTheRenderersFrame) {
  for (std::string_view name : {"gelsight-mini", "digit"}) {
    SCOPED_TRACE(std::string(name));
    auto camera = make_camera(name, 5);
    auto renderer = testing::make_renderer(name, 5);
    ASSERT_TRUE(camera && renderer);
    ContactScene s = sphere(6, 8);
    s.texture.sq_um = 10;
    s.loading.shear_x_n = 1;
    const RawFrame raw = render_raw(*camera, s, with_markers(), 3);
    const Frame direct = testing::render_ok(*renderer, s, with_markers(), 3);
    EXPECT_EQ(raw.processed.rgb, direct.rgb);
    EXPECT_EQ(raw.processed.state.force_n, direct.state.force_n);
    EXPECT_EQ(raw.processed.markers.size(), direct.markers.size());
  }
}

// Tolerances of the recovered frame against RawFrame::processed, with the profile's camera
// noise and without it. Measured (2 scenes x 2 seeds: a 5 mm ball at 4 N, a rough 10 mm ball at
// 8 N off centre; markers on): worst mean |d| / PSNR with noise, then quiet:
//   gelsight-mini  2.07 DN / 39.7 dB, 0.57 DN / 47.8 dB
//   digit          2.60 DN / 37.4 dB, 0.81 DN / 45.1 dB  (640x480: 2.62 / 37.3, 0.83 / 44.3)
//   gelsight-r1.5  1.83 DN / 40.6 dB, 0.86 DN / 45.5 dB
// Bounds: mean |d| x1.5, PSNR 2.5 dB lower (MSE x1.8). Why they are not 0:
// - YUYV: a pixel pair (along the processed y axis) shares its chroma, so the per-pixel colour
//   noise (sigma 5 DN on DIGIT) loses half its chroma; 8-bit rounding of Y/Cb/Cr and back.
// - R1.5 MJPEG q90 at the processed size: 4:2:2 chroma and DCT quantisation.
// - Mini MJPEG: the processed frame is enlarged 7.2x (bilinear), encoded, decoded at 1/8 (an
//   8x8 block average) and enlarged 1.115x back: about one processed pixel of blur, which costs
//   most on the camera noise and on marker and contact edges.
// The quiet bounds have teeth: a decode that misplaces the crop by 1 % of the raw frame (4.6
// processed px at the edges) gives 3.2 DN (raw_geometry_test.cc).
struct Bound {
  std::string_view sensor;
  double noisy_mean_abs_dn, noisy_psnr_db, quiet_mean_abs_dn, quiet_psnr_db;
};
constexpr Bound kBounds[] = {{"gelsight-mini", 3.1, 37.0, 0.85, 45.0},
                             {"digit", 3.9, 34.5, 1.25, 42.0},
                             {"digit-640x480", 3.9, 34.5, 1.25, 41.5},
                             {"gelsight-r1.5", 2.75, 38.0, 1.3, 43.0}};

TEST(SimRenderRaw, RecoveredFrameIsCloseToTheProcessedFrame) {
  ContactScene rough = sphere(8, 10);
  rough.texture.sq_um = 30;
  rough.geometry.center_x_mm = 2;
  const ContactScene scenes[] = {sphere(4), rough};
  RenderOptions quiet = testing::quiet();
  quiet.markers = true;
  for (const Bound& b : kBounds) {
    SCOPED_TRACE(std::string(b.sensor));
    auto camera = make_camera(b.sensor);
    auto decoder = make_decoder(b.sensor);
    ASSERT_TRUE(camera && decoder);
    for (const ContactScene& s : scenes) {
      for (uint64_t seed : {1, 2}) {
        const RawFrame noisy = render_raw(*camera, s, with_markers(), seed);
        const auto n = closeness(recover_ok(*decoder, noisy.bytes), noisy.processed.rgb);
        EXPECT_LE(n.mean_abs, b.noisy_mean_abs_dn) << "seed " << seed;
        EXPECT_GE(n.psnr_db, b.noisy_psnr_db) << "seed " << seed;
        const RawFrame clean = render_raw(*camera, s, quiet, seed);
        const auto q = closeness(recover_ok(*decoder, clean.bytes), clean.processed.rgb);
        EXPECT_LE(q.mean_abs, b.quiet_mean_abs_dn) << "seed " << seed;
        EXPECT_GE(q.psnr_db, b.quiet_psnr_db) << "seed " << seed;
      }
    }
  }
}

// Every extreme case renders through its sensor's raw camera, and recovery gives a frame of
// the processed size whose mean is that of the processed frame (a NaN turned into 0 or 255 in
// a region, or a misplaced crop on a saturated or black frame, would move it).
TEST(SimRenderRaw, ExtremeCasesRenderFiniteRawFrames) {
  constexpr double kMaxMeanShiftDn = 2.0;  // JPEG + resampling keep the mean within ~0.5 DN
  for (const ExtremeCase& c : extreme_cases()) {
    SCOPED_TRACE(c.name);
    auto camera = RawCamera::create(c.sensor, 1);
    auto decoder = RawDecoder::create(c.sensor);
    ASSERT_TRUE(camera.ok() && decoder.ok());
    RawFrame raw;
    const Status st = (*camera)->render(c.scene, c.options, 1, raw);
    ASSERT_TRUE(st.ok()) << st.error().message();
    EXPECT_TRUE(testing::finite_state(raw.processed.state));
    const auto rgb = recover_ok(**decoder, raw.bytes);
    ASSERT_EQ(rgb.size(), raw.processed.rgb.size());
    double a = 0, b = 0;
    for (size_t i = 0; i < rgb.size(); ++i) {
      a += rgb[i];
      b += raw.processed.rgb[i];
    }
    EXPECT_NEAR(a / static_cast<double>(rgb.size()), b / static_cast<double>(rgb.size()),
                kMaxMeanShiftDn);
  }
}

}  // namespace
}  // namespace tlvlink::sim
