// The sensor-view augmentation (tools/trainer/src/view_augment.*, view_optics.*): its image
// operations with fixed parameters, the chain's determinism and draws, and the component names.
// No libtorch.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "support/random.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/trainer/trainer.h"
#include "view_augment.h"
#include "view_optics.h"

namespace tlvlink::trainer {
namespace {

constexpr int32_t kW = 320, kH = 240;

// A GelSight-like frame: smooth colour gradients, a blob and fine texture.
std::vector<uint8_t> gel_frame(uint64_t seed) {
  testing::Rng rng(seed);
  std::vector<uint8_t> f(static_cast<size_t>(kW * kH * 3));
  for (int32_t y = 0; y < kH; ++y) {
    for (int32_t x = 0; x < kW; ++x) {
      const double blob =
          60 * std::exp(-((x - 160.0) * (x - 160.0) + (y - 120.0) * (y - 120.0)) / 800);
      for (int32_t c = 0; c < 3; ++c) {
        const double v =
            90 + 30 * c + 0.2 * x - 0.1 * y + blob * (c == 1 ? -1 : 1) + rng.int_in(-3, 3);
        f[(static_cast<size_t>(y) * kW + static_cast<size_t>(x)) * 3 + static_cast<size_t>(c)] =
            static_cast<uint8_t>(std::clamp(v, 0.0, 255.0));
      }
    }
  }
  return f;
}

struct Model {
  std::vector<float> mean{0.5f, 0.5f, 0.5f}, stdev{0.2f, 0.2f, 0.2f};
  InputSpec spec;
  Model() {
    spec.height = 96;
    spec.width = 128;
    spec.resize_filter = ResizeFilter::kArea;
    spec.mean = mean;
    spec.std = stdev;
  }
};

double mean_abs_diff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i)
    s += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
  return s / static_cast<double>(a.size());
}

TEST(ViewComponents, NamesParseBothWays) {
  EXPECT_EQ(parse_view_components("all").value(), static_cast<uint32_t>(kViewAll));
  EXPECT_EQ(parse_view_components("none").value(), 0u);
  EXPECT_EQ(parse_view_components("codec,blur").value(), kViewCodec | kViewBlur);
  EXPECT_EQ(view_components_name(kViewCodec | kViewBlur), "blur,codec");
  EXPECT_EQ(view_components_name(kViewAll), "all");
  EXPECT_EQ(view_components_name(0), "none");
  for (uint32_t bit = 1; bit < kViewAll; bit <<= 1) {
    EXPECT_EQ(parse_view_components(view_components_name(bit)).value(), bit);
  }
  auto bad = parse_view_components("codec,glare");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string(bad.error().message()).find("'glare'"), std::string::npos);
}

TEST(ViewOptics, IdentityParametersKeepTheFrame) {
  const std::vector<uint8_t> f8 = gel_frame(1);
  std::vector<float> f(f8.begin(), f8.end()), g(f.size()), scratch;
  view::warp(f.data(), g.data(), kW, kH, view::Affine{});
  for (size_t i = 0; i < f.size(); ++i)
    ASSERT_NEAR(g[i], f[i], 1e-3) << i;  // float bilinear at t=0
  view::shade(g.data(), kW, kH, view::Shading{});
  for (size_t i = 0; i < f.size(); ++i) ASSERT_EQ(g[i], f[i]) << i;  // x * 1 * 1 * 1 + 0
  std::vector<float> flat(f.size(), 100.0f);
  view::blur(flat.data(), kW, kH, 1.3, scratch);
  for (float v : flat) ASSERT_NEAR(v, 100.0f, 1e-3);  // normalised kernel, edges repeated
}

TEST(ViewOptics, EachOperationDoesWhatItSays) {
  // A one-pixel shift moves a column by one pixel (interior, away from repeated edges).
  std::vector<float> ramp(static_cast<size_t>(kW * kH * 3)), moved(ramp.size());
  for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<float>((i / 3) % kW);
  view::warp(ramp.data(), moved.data(), kW, kH, view::Affine{1, 0, 1, 0});
  EXPECT_NEAR(moved[(100 * kW + 50) * 3], 49.0f, 1e-3);
  // Vignetting darkens the corners more than the centre.
  std::vector<float> flat(ramp.size(), 200.0f);
  view::Shading s;
  s.vignette = 0.3;
  view::shade(flat.data(), kW, kH, s);
  EXPECT_LT(flat[0], flat[(120 * kW + 160) * 3] - 50);
  // A speck darkens its centre by `darkness` and leaves far pixels alone.
  std::vector<float> dusty(ramp.size(), 200.0f);
  view::darken(dusty.data(), kW, kH, view::Speck{100.5, 50.5, 2, 0.5});
  EXPECT_NEAR(dusty[(50 * kW + 100) * 3], 100.0f, 0.5f);
  EXPECT_EQ(dusty[(50 * kW + 120) * 3], 200.0f);
  // Noise of sigma 2 DN: the sample std over 230k values within 2 % (its standard error is
  // ~0.15 %), mean within 0.02 DN.
  std::vector<float> noisy(ramp.size(), 128.0f);
  view::add_noise(noisy.data(), noisy.size(), 2.0, 99);
  const double mean =
      std::accumulate(noisy.begin(), noisy.end(), 0.0) / static_cast<double>(noisy.size());
  double var = 0;
  for (float v : noisy) var += (static_cast<double>(v) - mean) * (static_cast<double>(v) - mean);
  EXPECT_NEAR(mean, 128.0, 0.02);
  EXPECT_NEAR(std::sqrt(var / static_cast<double>(noisy.size())), 2.0, 0.04);
}

TEST(ViewAugmenter, NoComponentIsTheModelsOwnResize) {
  Model m;
  auto a = ViewAugmenter::create(kW, kH, m.spec);
  ASSERT_TRUE(a.ok()) << a.error().message();
  const std::vector<uint8_t> f = gel_frame(2);
  std::vector<uint8_t> out(96 * 128 * 3);
  ViewDraw draw;
  ASSERT_TRUE(a->make(f, 0, 5, out, &draw).ok());
  EXPECT_EQ(draw.applied, 0u);
  auto plain = image::resize({f.data(), kW, kH, 3, 0}, 96, 128, ResizeFilter::kArea);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(out, plain->pixels);
}

TEST(ViewAugmenter, SameSeedSameBytesAndTheDrawsFollowTheProbabilities) {
  Model m;
  auto a = ViewAugmenter::create(kW, kH, m.spec);
  auto b = ViewAugmenter::create(kW, kH, m.spec);
  ASSERT_TRUE(a.ok() && b.ok());
  const std::vector<uint8_t> f = gel_frame(3);
  std::vector<uint8_t> x(96 * 128 * 3), y(x.size()), clean(x.size());
  ASSERT_TRUE(a->make(f, 0, 1, clean).ok());
  constexpr int kViews = 300;
  int codec = 0, jpeg = 0, mjpeg = 0, yuyv = 0, differ = 0;
  double moved = 0;
  for (int i = 0; i < kViews; ++i) {
    const uint64_t seed = view_seed(7, i, i * 3, i % 2);
    ViewDraw d1, d2;
    ASSERT_TRUE(a->make(f, kViewAll, seed, x, &d1).ok());
    ASSERT_TRUE(b->make(f, kViewAll, seed, y, &d2).ok());
    ASSERT_EQ(x, y) << "view " << i;  // another augmenter, same seed: same bytes
    ASSERT_EQ(d1.applied, d2.applied);
    if (d1.applied & kViewCodec) ++codec;
    jpeg += d1.codec == ViewDraw::Codec::kJpeg;
    mjpeg += d1.codec == ViewDraw::Codec::kMjpegScaled;
    yuyv += d1.codec == ViewDraw::Codec::kYuyv;
    if (d1.applied != 0) differ += x != clean;
    // Without the photometric components a view keeps the frame's levels: what is left
    // (mounting, dust, focus, noise, codec) moves pixels, not the picture.
    ASSERT_TRUE(
        a->make(f, kViewAll & ~(kViewColour | kViewVignette | kViewLedDrift), seed, y).ok());
    moved += mean_abs_diff(y, clean);
  }
  // Codec drawn with p 0.75: 225 of 300 expected, binomial sd 7.5; 4 sd either side.
  EXPECT_NEAR(codec, 225, 30);
  EXPECT_EQ(jpeg + mjpeg + yuyv, codec);
  EXPECT_GT(jpeg, 0);
  EXPECT_GT(mjpeg, 0);
  EXPECT_GT(yuyv, 0);
  EXPECT_GT(differ, kViews * 9 / 10);
  // ~2 DN of mean absolute change on this frame (its gradients under a +-3 % shift, noise,
  // codec); 5 DN would mean an operation changes levels it should not.
  EXPECT_LT(moved / kViews, 5.0);
}

TEST(ViewAugmenter, AComponentLeftOutDoesNotMoveTheOthersDraws) {
  // Ablations compare runs that differ in one component; the others must draw the same values.
  Model m;
  auto a = ViewAugmenter::create(kW, kH, m.spec);
  ASSERT_TRUE(a.ok());
  const std::vector<uint8_t> f = gel_frame(5);
  std::vector<uint8_t> x(96 * 128 * 3);
  for (int i = 0; i < 50; ++i) {
    ViewDraw all, no_blur;
    ASSERT_TRUE(a->make(f, kViewAll, 1000 + i, x, &all).ok());
    ASSERT_TRUE(a->make(f, kViewAll & ~kViewBlur, 1000 + i, x, &no_blur).ok());
    EXPECT_EQ(all.applied & ~kViewBlur, no_blur.applied) << i;
    EXPECT_EQ(all.codec, no_blur.codec) << i;
    EXPECT_EQ(all.quality, no_blur.quality) << i;
  }
}

TEST(ViewAugmenter, ACodecTwinDiffersByTheCodecAlone) {
  // --codec-pairs: the second view is the first through another codec draw, every other draw
  // the same (the pair a frame and its re-encoding make).
  Model m;
  auto a = ViewAugmenter::create(kW, kH, m.spec);
  ASSERT_TRUE(a.ok());
  const std::vector<uint8_t> f = gel_frame(8);
  std::vector<uint8_t> x(96 * 128 * 3), y(x.size());
  int both_coded = 0, one_coded = 0;
  for (int i = 0; i < 60; ++i) {
    const uint64_t seed = view_seed(3, i, i, 0), twin_seed = view_seed(3, i, i, 1);
    // Without the codec the twin is the original, byte for byte.
    const uint32_t no_codec = kViewAll & ~kViewCodec;
    ASSERT_TRUE(a->make(f, no_codec, seed, x).ok());
    ASSERT_TRUE(a->make_codec_twin(f, no_codec, seed, twin_seed, y).ok());
    ASSERT_EQ(x, y) << i;
    ViewDraw d, t;
    ASSERT_TRUE(a->make(f, kViewAll, seed, x, &d).ok());
    ASSERT_TRUE(a->make_codec_twin(f, kViewAll, seed, twin_seed, y, &t).ok());
    EXPECT_EQ(d.applied & no_codec, t.applied & no_codec) << i;
    EXPECT_EQ(d.blur_sigma, t.blur_sigma) << i;
    EXPECT_EQ(d.noise_dn, t.noise_dn) << i;
    const bool dc = (d.applied & kViewCodec) != 0, tc = (t.applied & kViewCodec) != 0;
    both_coded += dc && tc;
    one_coded += dc != tc;
    // Only the link differs: the two inputs stay within a codec's few DN (mean), where two
    // independent views of this frame move ~2 DN more (geometry, colour).
    EXPECT_LT(mean_abs_diff(x, y), 3.0) << i;
    if (!dc && !tc) {
      EXPECT_EQ(x, y) << i;
    }
  }
  // Each side coded with p 0.75: both ~34 of 60, exactly one ~22; wide bounds (>= 4 sd).
  EXPECT_GT(both_coded, 20);
  EXPECT_GT(one_coded, 8);
}

TEST(ViewAugmenter, PortraitFramesAreMadeAtTheirOwnSize) {
  // A DIGIT frame is 240 wide and 320 high and its camera sends it transposed: its views keep
  // that shape until the model's resize, exactly as the board resizes it.
  Model m;
  auto a = ViewAugmenter::create(kH, kW, m.spec, image::Orientation::kTransposed);
  ASSERT_TRUE(a.ok()) << a.error().message();
  const std::vector<uint8_t> f = gel_frame(6);  // 230,400 bytes read as 240x320
  std::vector<uint8_t> out(96 * 128 * 3);
  ASSERT_TRUE(a->make(f, 0, 1, out).ok());
  auto plain = image::resize({f.data(), kH, kW, 3, 0}, 96, 128, ResizeFilter::kArea);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(out, plain->pixels);
  int yuyv = 0;
  for (uint64_t seed = 0; seed < 100 && yuyv == 0; ++seed) {
    ViewDraw d;
    ASSERT_TRUE(a->make(f, kViewCodec, seed, out, &d).ok());
    yuyv += d.codec == ViewDraw::Codec::kYuyv;
  }
  EXPECT_GT(yuyv, 0);  // the transposed YUYV round trip runs
}

TEST(ViewAugmenter, RefusesWhatItCannotMake) {
  Model m;
  EXPECT_EQ(ViewAugmenter::create(321, 240, m.spec).error().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(ViewAugmenter::create(320, 241, m.spec).error().code(), ErrorCode::kInvalidArgument);
  m.spec.crop_w = 100;
  m.spec.crop_h = 100;
  EXPECT_EQ(ViewAugmenter::create(320, 240, m.spec).error().code(), ErrorCode::kInvalidArgument);
  Model ok;
  auto a = ViewAugmenter::create(kW, kH, ok.spec);
  ASSERT_TRUE(a.ok());
  std::vector<uint8_t> small(100), out(96 * 128 * 3);
  EXPECT_EQ(a->make(small, kViewAll, 1, out).error().code(), ErrorCode::kShapeMismatch);
}

}  // namespace
}  // namespace tlvlink::trainer
