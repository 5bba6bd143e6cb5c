// ONNX-imported models (tests/onnx: exported with Debian's python3-torch, BatchNorm folded,
// ReLU/Clip fused, residuals, SE blocks, sigmoid, pads, pools) as the quantizer's float input:
// each quantizes with every op int8 or with a stated fp32 fallback, loads, runs on XNNPACK, and
// tracks the float model on held-out frames.

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/io/file.h"
#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/layer_error.h"
#include "tlvlink/quantize/onnx_import.h"
#include "tlvlink/quantize/quantizer.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> parity_models() {
  std::ifstream f(fs::path(TLVLINK_ONNX_MODELS) / "manifest.txt");
  std::vector<std::string> names;
  std::string kind, name;
  while (f >> kind >> name) {
    if (kind == "parity") names.push_back(name);
    std::string rest;
    std::getline(f, rest);
  }
  return names;
}

TEST(QuantizeOnnx, EveryParityModelQuantizesAndTracksFloat) {
  const std::vector<std::string> names = parity_models();
  ASSERT_FALSE(names.empty()) << "no manifest in " << TLVLINK_ONNX_MODELS
                              << " (fixture onnx.make_models)";
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    auto bytes =
        tools::read_file((fs::path(TLVLINK_ONNX_MODELS) / (name + ".onnx")).string(), 1 << 26);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message();
    quantize::OnnxImportOptions io;
    io.source_name = name + ".onnx";
    auto imported = quantize::import_onnx(*bytes, io);
    ASSERT_TRUE(imported.ok()) << imported.error().message();
    auto fp32 = testing::load_model(imported->model);
    ASSERT_NE(fp32, nullptr);
    quantize::CalibDataOptions d;
    d.paths = {"extreme"};
    d.calib_count = 16;
    d.heldout_count = 6;
    d.progress = false;
    auto data = quantize::load_calib_data(d, fp32->metadata().input);
    ASSERT_TRUE(data.ok()) << data.error().message();
    auto stats = quantize::calibrate(*fp32, data->calibration);
    ASSERT_TRUE(stats.ok()) << stats.error().message();
    auto q = quantize::quantize_model(*fp32, quantize::select_ranges(*stats, {}), {});
    ASSERT_TRUE(q.ok()) << q.error().message();
    for (const quantize::LayerDecision& l : q->layers) {
      if (l.precision == quantize::LayerPrecision::kFloat && l.fused_into.empty()) {
        EXPECT_FALSE(l.reason.empty()) << l.op;
      }
    }
    auto int8 = testing::load_model(q->builder.finish());
    ASSERT_NE(int8, nullptr);
    auto x = make_executor(*int8, ExecutorKind::kXnnpack);
    EXPECT_TRUE(x.ok() || x.error().code() == ErrorCode::kModelUnsupported) << x.error().message();
    auto e = quantize::compare_models(*fp32, *int8, data->heldout);
    ASSERT_TRUE(e.ok()) << e.error().message();
    // Small random-weight nets, 16 calibration frames, held-out frames of other scenes.
    constexpr double kMinCosine = 0.98;
    EXPECT_GT(e->mean_cosine(), kMinCosine) << "int8 " << q->int8_ops << ", fp32 " << q->float_ops;
  }
}

}  // namespace
}  // namespace tlvlink
