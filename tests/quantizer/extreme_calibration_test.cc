// Calibration on the simulator's extreme frame set (all black, saturated, full contact,
// checkerboards, noise only, ...) through the CLI's data path and the deployment preprocessing:
// the reference encoder still quantizes fully to int8 with every method, XNNPACK accepts the
// result, and its outputs on held-out extreme frames are finite and close to fp32.

#include <cmath>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/quantizer.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

TEST(ExtremeCalibration, ReferenceEncoderQuantizesFullyWithEveryMethod) {
  quantize::ReferenceEncoderOptions eo;
  eo.resolution = 96;
  eo.seed = 5;
  eo.golden_pairs = 0;
  eo.preprocess = quantize::deployment_preprocessor();
  auto enc = quantize::build_reference_encoder(eo);
  ASSERT_TRUE(enc.ok()) << enc.error().message();
  auto fp32 = testing::load_model(enc->file);
  ASSERT_NE(fp32, nullptr);

  quantize::CalibDataOptions d;
  d.paths = {"extreme"};
  d.calib_count = 24;
  d.heldout_count = 8;
  d.seed = 3;
  d.progress = false;
  auto data = quantize::load_calib_data(d, fp32->metadata().input);
  ASSERT_TRUE(data.ok()) << data.error().message();
  EXPECT_EQ(data->formats, std::vector<quantize::CalibFormat>{quantize::CalibFormat::kExtreme});
  ASSERT_EQ(data->calibration.size(), 24u);
  ASSERT_EQ(data->heldout.size(), 8u);

  auto stats = quantize::calibrate(*fp32, data->calibration);
  ASSERT_TRUE(stats.ok()) << stats.error().message();
  for (quantize::CalibrationMethod method : quantize::kAllCalibrationMethods) {
    SCOPED_TRACE(quantize::calibration_method_name(method));
    quantize::CalibrationOptions c;
    c.method = method;
    auto q = quantize::quantize_model(*fp32, quantize::select_ranges(*stats, c), {});
    ASSERT_TRUE(q.ok()) << q.error().message();
    EXPECT_EQ(q->float_ops, 0u);
    auto int8 = testing::load_model(q->builder.finish());  // every scale finite and normal
    ASSERT_NE(int8, nullptr);
    auto x = make_executor(*int8, ExecutorKind::kXnnpack);
    ASSERT_TRUE(x.ok() || x.error().code() == ErrorCode::kModelUnsupported) << x.error().message();
    // compare_models fails on a non-finite output (the executors check outputs).
    quantize::CompareOptions co;
    co.per_layer = false;
    auto e = quantize::compare_models(*fp32, *int8, data->heldout, co);
    ASSERT_TRUE(e.ok()) << e.error().message();
    EXPECT_TRUE(std::isfinite(e->mean_cosine()));
    // Random weights on very unusual frames. minmax / percentile / mse measured >= 0.998 per
    // frame, entropy 0.98; ema's moving average is dominated by the first of 24 wildly different
    // scenes and clips the others (measured min 0.83). The floors still catch a broken layer
    // (all-clipped or flushed to zero), which drops the cosine far lower.
    const bool ema = method == quantize::CalibrationMethod::kEma;
    EXPECT_GT(e->min_cosine(), ema ? 0.7 : 0.97);
    EXPECT_GT(e->mean_cosine(), ema ? 0.9 : 0.99);
  }
}

}  // namespace
}  // namespace tlvlink
