// The reference encoder generator: MAC budget, determinism, metadata, healthy activation
// ranges, and the int8 form against the fp32 form.

#include <algorithm>
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/inspect/graph_stats.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

using quantize::EncoderDType;
using quantize::ReferenceEncoderOptions;

// The budget for the edge encoder.
constexpr double kMinMmac = 20.0, kMaxMmac = 60.0;
// MACs scale with the pixel count; stride-2 rounding at odd sizes moves it by a few percent.
constexpr double kScalingTolerance = 0.05;
// int8 vs fp32 embedding cosine. 8-bit per-tensor activations cost ~40 dB SQNR per layer and the
// error compounds over ~30 layers; the notes measured 0.9997 on a similar net. 0.98 leaves room
// for fresh frames leaving the calibrated ranges, while a wrong scale, zero point or channel axis
// drops the cosine far below it.
constexpr double kMinInt8Cosine = 0.98;
// Activations "neither explode nor vanish": every layer's largest magnitude stays in this band
// (inputs are normalised to [-2, 2]; ReLU6 caps most layers at 6).
constexpr float kMinLayerPeak = 0.05f, kMaxLayerPeak = 50.0f;

ReferenceEncoderOptions options(EncoderDType dtype, int32_t resolution = 128) {
  ReferenceEncoderOptions o;
  o.dtype = dtype;
  o.resolution = resolution;
  o.seed = 11;
  o.calibration_frames = 8;
  o.preprocess = quantize::deployment_preprocessor();
  return o;
}

std::vector<float> run(Executor& e, const std::vector<float>& x) {
  std::memcpy(e.input(0).data(), x.data(), e.input(0).size());
  const Status s = e.invoke();
  EXPECT_TRUE(s.ok()) << s.error().message();
  const auto out = e.output(0);
  const auto* f = reinterpret_cast<const float*>(out.data());
  return {f, f + out.size() / sizeof(float)};
}

double cosine(const std::vector<float>& a, const std::vector<float>& b) {
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ab += static_cast<double>(a[i]) * static_cast<double>(b[i]);
    aa += static_cast<double>(a[i]) * static_cast<double>(a[i]);
    bb += static_cast<double>(b[i]) * static_cast<double>(b[i]);
  }
  return ab / std::sqrt(aa * bb);
}

TEST(ReferenceEncoder, MacsWithinBudgetAndScaleWithResolution) {
  const double m128 = static_cast<double>(quantize::reference_encoder_macs(128)) / 1e6;
  EXPECT_GE(m128, kMinMmac);
  EXPECT_LE(m128, kMaxMmac);
  for (int32_t r : {96, 112, 144, 160}) {
    const double m = static_cast<double>(quantize::reference_encoder_macs(r)) / 1e6;
    EXPECT_GE(m, kMinMmac) << r;
    EXPECT_LE(m, kMaxMmac) << r;
    const double expected = m128 * (r / 128.0) * (r / 128.0);
    EXPECT_NEAR(m / expected, 1.0, kScalingTolerance) << "resolution " << r << ": " << m << " MMAC";
  }
}

TEST(ReferenceEncoder, Fp32LoadsWithMetadataAndIndependentMacCount) {
  auto enc = quantize::build_reference_encoder(options(EncoderDType::kFloat32));
  ASSERT_TRUE(enc.ok()) << enc.error().message();
  auto model = testing::load_model(enc->file);
  ASSERT_NE(model, nullptr);
  // The builder's own count and inspect's count from the loaded graph agree.
  EXPECT_EQ(inspect::graph_stats(model->graph()).macs, enc->macs);
  const Metadata& m = model->metadata();
  EXPECT_EQ(m.input.height, 128);
  EXPECT_EQ(m.input.channel_order, ChannelOrder::kRGB);
  EXPECT_EQ(m.embedding_dim, 128);
  ASSERT_EQ(m.linear_heads.size(), 3u);
  EXPECT_EQ(m.linear_heads[0].name, "material");
  EXPECT_EQ(m.linear_heads[0].labels.size(), 20u);
  EXPECT_EQ(m.linear_heads[0].labels[9], "natural fabric");
  EXPECT_TRUE(m.grasp_head.present);
  EXPECT_NE(m.provenance.training.find("\"kind\":\"random-reference\",\"seed\":11"),
            std::string_view::npos);
  EXPECT_EQ(m.golden.size(), 2u);
}

TEST(ReferenceEncoder, SameSeedSameWeightsOtherSeedOtherWeights) {
  auto a = quantize::build_reference_encoder(options(EncoderDType::kFloat32));
  auto b = quantize::build_reference_encoder(options(EncoderDType::kFloat32));
  ReferenceEncoderOptions o = options(EncoderDType::kFloat32);
  o.seed = 12;
  auto c = quantize::build_reference_encoder(o);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  auto ma = testing::load_model(a->file), mb = testing::load_model(b->file),
       mc = testing::load_model(c->file);
  ASSERT_TRUE(ma && mb && mc);
  EXPECT_EQ(ma->metadata().provenance.content_checksum, mb->metadata().provenance.content_checksum);
  EXPECT_NE(ma->metadata().provenance.content_checksum, mc->metadata().provenance.content_checksum);
  EXPECT_EQ(quantize::synthetic_touch_frame(40, 30, 5), quantize::synthetic_touch_frame(40, 30, 5));
  EXPECT_NE(quantize::synthetic_touch_frame(40, 30, 5), quantize::synthetic_touch_frame(40, 30, 6));
}

TEST(ReferenceEncoder, ActivationsNeitherExplodeNorVanish) {
  auto enc = quantize::build_reference_encoder(options(EncoderDType::kFloat32));
  ASSERT_TRUE(enc.ok());
  auto model = testing::load_model(enc->file);
  ASSERT_NE(model, nullptr);
  std::vector<std::vector<float>> frames;
  for (uint64_t s = 0; s < 4; ++s) {
    auto x = quantize::synthetic_input(*model, 500 + s);
    ASSERT_TRUE(x.ok());
    frames.push_back(std::move(*x));
  }
  auto ranges = quantize::collect_ranges(*model, frames);
  ASSERT_TRUE(ranges.ok()) << ranges.error().message();
  for (const Operator& op : model->graph().operators) {
    const quantize::TensorRange& r = (*ranges)[static_cast<size_t>(op.output)];
    const float peak = std::max(std::fabs(r.min), std::fabs(r.max));
    EXPECT_GE(peak, kMinLayerPeak) << op.name;
    EXPECT_LE(peak, kMaxLayerPeak) << op.name;
  }
}

TEST(ReferenceEncoder, Int8FormIsWellFormedAndTracksFp32OnFreshFrames) {
  auto f = quantize::build_reference_encoder(options(EncoderDType::kFloat32));
  auto q = quantize::build_reference_encoder(options(EncoderDType::kInt8));
  ASSERT_TRUE(f.ok()) << f.error().message();
  ASSERT_TRUE(q.ok()) << q.error().message();
  auto mf = testing::load_model(f->file), mq = testing::load_model(q->file);
  ASSERT_TRUE(mf && mq);
  const Graph& g = mq->graph();
  EXPECT_EQ(g.operators.front().type, OpType::kQuantize);
  EXPECT_EQ(g.operators.back().type, OpType::kDequantize);
  EXPECT_EQ(g.tensor(g.inputs[0]).dtype, DType::kFloat32);
  EXPECT_EQ(g.tensor(g.outputs[0]).dtype, DType::kFloat32);
  for (const Operator& op : g.operators) {
    if (op.type != OpType::kConv2D && op.type != OpType::kFullyConnected) continue;
    const Tensor& w = g.tensor(op.inputs[1]);
    EXPECT_EQ(w.dtype, DType::kInt8) << op.name;
    EXPECT_EQ(w.quant.axis, 0) << op.name;
    EXPECT_EQ(w.quant.scale.size(), static_cast<size_t>(w.shape[0])) << op.name;
  }
  EXPECT_EQ(mq->metadata().golden.size(), 2u);
  EXPECT_NE(mq->metadata().provenance.quantization.find("post-training-minmax"),
            std::string_view::npos);

  auto ef = make_reference_executor(*mf), eq = make_reference_executor(*mq);
  ASSERT_TRUE(ef.ok() && eq.ok());
  double worst = 1.0;
  for (uint64_t s = 0; s < 4; ++s) {  // seeds disjoint from calibration and golden frames
    auto x = quantize::synthetic_input(*mf, 90000 + s);
    ASSERT_TRUE(x.ok());
    worst = std::min(worst, cosine(run(**ef, *x), run(**eq, *x)));
  }
  std::printf("int8 vs fp32 embedding cosine (worst of 4 fresh frames): %.5f\n", worst);
  EXPECT_GE(worst, kMinInt8Cosine);
}

}  // namespace
}  // namespace tlvlink
