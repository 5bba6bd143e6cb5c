// ONNX import against torch: every model make_onnx_models.py exports (Debian's python3-torch,
// run by the CTest fixture onnx.make_models) is converted and run on both executors, and the
// output is compared with the one torch computed. Models outside the supported set must fail
// with an error naming the op type and the node; corrupt files must fail cleanly.

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "support/random.h"
#include "tlvlink/executor.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/onnx_import.h"

namespace tlvlink {
namespace {

using quantize::import_onnx;
using quantize::OnnxImportOptions;

const std::string kModels = TLVLINK_ONNX_MODELS;

// Parity tolerance, relative to the output's largest magnitude. torch (oneDNN) and the runtime
// sum the same products in different orders (and XNNPACK with FMA, blocked by channel); BatchNorm
// folding rounds w*a once more. For fp32 with K <= ~600 products per output and a few layers,
// that stays near 1e-6 relative; 1e-4 leaves headroom for XNNPACK's sigmoid (a few ulp) while a
// wrong layout, pad or fold is off by O(1).
constexpr double kMaxRelativeError = 1e-4;
// Cosine floor: any transposed or permuted weight drives it far below this.
constexpr double kMinCosine = 0.999999;

const char* const kParityModels[] = {"conv_dense_relu",
                                     "conv_strided_dilated",
                                     "conv_depthwise",
                                     "conv_grouped",
                                     "conv_auto_pad",
                                     "batchnorm",
                                     "relu6_clip",
                                     "relu6_clip_opset9",
                                     "residual_add",
                                     "mul_div_sub",
                                     "gap_linear_sigmoid",
                                     "maxpool",
                                     "flatten_spatial",
                                     "view_matmul",
                                     "gemm_matmul",
                                     "pad",
                                     "pad_opset9",
                                     "mobilenetv2_blocks",
                                     "mobilenetv2_blocks_opset17",
                                     "gray_dynamic_batch",
                                     "se_block"};
const char* const kRejectModels[] = {"reject_softmax", "reject_lstm", "reject_nan_weight",
                                     "reject_dynamic_size", "reject_reflect_pad"};

struct Manifest {
  std::set<std::string> parity;
  std::map<std::string, std::vector<std::string>> reject;  // name -> expected substrings
};

Manifest read_manifest() {
  Manifest m;
  std::ifstream in(kModels + "/manifest.txt");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string kind, name;
    fields >> kind >> name;
    if (kind == "parity") m.parity.insert(name);
    if (kind != "reject") continue;
    std::string rest, part;
    std::getline(fields >> std::ws, rest);
    std::istringstream parts(rest);
    while (std::getline(parts, part, '|')) m.reject[name].push_back(part);
  }
  return m;
}

std::vector<std::byte> onnx_file(const std::string& name) {
  auto bytes = tools::read_file(kModels + "/" + name + ".onnx", size_t{1} << 30);
  EXPECT_TRUE(bytes.ok()) << bytes.error().message()
                          << " (the CTest fixture onnx.make_models writes it; run via ctest)";
  return bytes.ok() ? std::move(bytes).value() : std::vector<std::byte>{};
}

tools::NpyArray npy(const std::string& path) {
  auto a = tools::read_npy(path);
  EXPECT_TRUE(a.ok()) << a.error().message();
  return a.ok() ? std::move(a).value() : tools::NpyArray{};
}

// [N, C, H, W] -> [N, H, W, C]; other ranks unchanged.
std::vector<float> to_nhwc(const tools::NpyArray& a) {
  std::span<const float> v = a.as<float>();
  if (a.shape.size() != 4) return {v.begin(), v.end()};
  const int64_t c = a.shape[1], h = a.shape[2], w = a.shape[3];
  std::vector<float> out(v.size());
  for (int64_t y = 0; y < h; ++y) {
    for (int64_t x = 0; x < w; ++x) {
      for (int64_t k = 0; k < c; ++k)
        out[static_cast<size_t>((y * w + x) * c + k)] = v[static_cast<size_t>((k * h + y) * w + x)];
    }
  }
  return out;
}

struct Parity {
  double max_abs = 0, max_ref = 0, cosine = 0;
};

Parity compare(std::span<const float> got, std::span<const float> want) {
  Parity p;
  double ab = 0, aa = 0, bb = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    const double a = got[i], b = want[i];
    p.max_abs = std::max(p.max_abs, std::fabs(a - b));
    p.max_ref = std::max(p.max_ref, std::fabs(b));
    ab += a * b;
    aa += a * a;
    bb += b * b;
  }
  p.cosine = ab / std::sqrt(aa * bb);
  return p;
}

Result<quantize::OnnxImportResult> convert(const std::string& name,
                                           OnnxImportOptions o = OnnxImportOptions{}) {
  o.source_name = name + ".onnx";
  return import_onnx(onnx_file(name), o);
}

size_t count_ops(const Model& m, OpType type) {
  size_t n = 0;
  for (const Operator& op : m.graph().operators) n += op.type == type;
  return n;
}

std::string param_name(const ::testing::TestParamInfo<const char*>& p) { return p.param; }

TEST(OnnxModels, ManifestListsExactlyTheTestedModels) {
  const Manifest m = read_manifest();
  EXPECT_EQ(m.parity, std::set<std::string>(std::begin(kParityModels), std::end(kParityModels)))
      << "make_onnx_models.py and this test disagree on the parity models";
  std::set<std::string> reject;
  for (const auto& [name, expected] : m.reject) reject.insert(name);
  EXPECT_EQ(reject, std::set<std::string>(std::begin(kRejectModels), std::end(kRejectModels)));
}

class OnnxParity : public ::testing::TestWithParam<const char*> {};

TEST_P(OnnxParity, RuntimeMatchesTorchOnBothExecutors) {
  const std::string name = GetParam();
  auto converted = convert(name);
  ASSERT_TRUE(converted.ok()) << converted.error().message();
  auto model = Model::load(converted->model);
  ASSERT_TRUE(model.ok()) << model.error().message();
  const tools::NpyArray input = npy(kModels + "/" + name + ".input.npy");
  const tools::NpyArray output = npy(kModels + "/" + name + ".output.npy");
  const std::vector<float> x = to_nhwc(input), want = to_nhwc(output);

  const Graph& g = (*model)->graph();
  ASSERT_EQ(g.tensor(g.inputs[0]).shape.elements(), x.size());
  ASSERT_EQ(g.tensor(g.outputs[0]).shape.elements(), want.size());
  for (ExecutorKind kind : {ExecutorKind::kReference, ExecutorKind::kXnnpack}) {
    SCOPED_TRACE(executor_kind_name(kind));
    auto exec = make_executor(**model, kind);
    ASSERT_TRUE(exec.ok()) << exec.error().message();
    std::memcpy((*exec)->input(0).data(), x.data(), x.size() * sizeof(float));
    const Status s = (*exec)->invoke();
    ASSERT_TRUE(s.ok()) << s.error().message();
    const auto out = (*exec)->output(0);
    const Parity p = compare({reinterpret_cast<const float*>(out.data()), want.size()}, want);
    std::printf("[parity] %-28s %-9s max-abs %.3g (max |torch| %.3g)  cosine %.9f\n", name.c_str(),
                executor_kind_name(kind), p.max_abs, p.max_ref, p.cosine);
    EXPECT_LE(p.max_abs, kMaxRelativeError * std::max(1.0, p.max_ref));
    EXPECT_GE(p.cosine, kMinCosine);
  }
}

INSTANTIATE_TEST_SUITE_P(Torch, OnnxParity, ::testing::ValuesIn(kParityModels), param_name);

class OnnxReject : public ::testing::TestWithParam<const char*> {};

TEST_P(OnnxReject, ErrorNamesTheCause) {
  const std::string name = GetParam();
  const Manifest m = read_manifest();
  ASSERT_EQ(m.reject.count(name), 1u) << name << " missing from manifest.txt";
  auto converted = convert(name);
  ASSERT_FALSE(converted.ok()) << name << " converted, but must be rejected";
  const std::string message = converted.error().message();
  for (const std::string& part : m.reject.at(name)) {
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
  EXPECT_TRUE(converted.error().code() == ErrorCode::kModelUnsupported ||
              converted.error().code() == ErrorCode::kModelInvalidTensor)
      << error_code_name(converted.error().code());
}

INSTANTIATE_TEST_SUITE_P(Torch, OnnxReject, ::testing::ValuesIn(kRejectModels), param_name);

TEST(OnnxCorrupt, TruncatedFilesAreCleanErrors) {
  const std::vector<std::byte> full = onnx_file("mobilenetv2_blocks");
  ASSERT_GT(full.size(), 1000u);
  for (double fraction : {0.0, 0.001, 0.1, 0.5, 0.9, 0.999}) {
    const auto size = std::max<size_t>(1, static_cast<size_t>(fraction * full.size()));
    auto r = import_onnx(std::span(full).first(size), OnnxImportOptions{});
    ASSERT_FALSE(r.ok()) << "truncated to " << size << " of " << full.size() << " bytes";
    EXPECT_GT(std::strlen(r.error().message()), 20u);
  }
  auto one_short = import_onnx(std::span(full).first(full.size() - 1), OnnxImportOptions{});
  ASSERT_FALSE(one_short.ok());
  EXPECT_EQ(one_short.error().code(), ErrorCode::kFormat) << one_short.error().message();
}

TEST(OnnxCorrupt, FlippedBytesNeverCrash) {
  const std::vector<std::byte> full = onnx_file("conv_depthwise");
  ASSERT_FALSE(full.empty());
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  testing::Rng rng(seed);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::byte> bad = full;
    for (int k = 0; k < 4; ++k) {
      bad[static_cast<size_t>(rng.int_in(0, static_cast<int32_t>(bad.size()) - 1))] =
          static_cast<std::byte>(rng.int_in(0, 255));
    }
    auto r = import_onnx(bad, OnnxImportOptions{});
    // Either a clean error or a model that loads (a flipped weight is still a model).
    if (r.ok())
      EXPECT_TRUE(Model::load(r->model).ok());
    else
      EXPECT_GT(std::strlen(r.error().message()), 10u);
  }
}

TEST(OnnxOptions, MetadataRecordsInputSpecEmbeddingAndProvenance) {
  OnnxImportOptions o;
  o.mean = {0.5f};
  o.std = {0.25f, 0.5f, 1.0f};
  o.channel_order = ChannelOrder::kBGR;
  o.model_name = "mnv2-test";
  auto converted = convert("mobilenetv2_blocks", o);
  ASSERT_TRUE(converted.ok()) << converted.error().message();
  auto model = Model::load(converted->model);
  ASSERT_TRUE(model.ok());
  const Metadata& md = (*model)->metadata();
  EXPECT_EQ(md.name, "mnv2-test");
  EXPECT_EQ(md.input.height, 64);
  EXPECT_EQ(md.input.width, 64);
  EXPECT_EQ(md.input.channels, 3);
  EXPECT_EQ(md.input.channel_order, ChannelOrder::kBGR);
  EXPECT_EQ(std::vector<float>(md.input.mean.begin(), md.input.mean.end()),
            std::vector<float>(3, 0.5f));
  EXPECT_EQ(std::vector<float>(md.input.std.begin(), md.input.std.end()), o.std);
  EXPECT_EQ(md.embedding_dim, 32);
  EXPECT_EQ(md.provenance.producer, "tlvlink convert");
  EXPECT_NE(md.provenance.training.find("\"source\":\"mobilenetv2_blocks.onnx\""),
            std::string_view::npos)
      << md.provenance.training;
  EXPECT_NE(md.provenance.training.find("\"opset\":13"), std::string_view::npos);
  EXPECT_EQ(converted->summary.opset, 13);
  EXPECT_EQ(converted->summary.input_shape, (std::vector<int32_t>{1, 64, 64, 3}));
}

TEST(OnnxOptions, DefaultsAreIdentityNormalisationAndGrayForOneChannel) {
  auto converted = convert("gray_dynamic_batch");
  ASSERT_TRUE(converted.ok()) << converted.error().message();
  auto model = Model::load(converted->model);
  ASSERT_TRUE(model.ok());
  const InputSpec& in = (*model)->metadata().input;
  EXPECT_EQ(in.channels, 1);
  EXPECT_EQ(in.channel_order, ChannelOrder::kGray);
  EXPECT_EQ(in.mean[0], 0.0f);
  EXPECT_EQ(in.std[0], 1.0f);
}

TEST(OnnxOptions, BadOptionsAreInvalidArgument) {
  OnnxImportOptions two_means;
  two_means.mean = {0.1f, 0.2f};
  OnnxImportOptions zero_std;
  zero_std.std = {0.0f};
  OnnxImportOptions gray_on_rgb;
  gray_on_rgb.channel_order = ChannelOrder::kGray;
  for (const OnnxImportOptions& o : {two_means, zero_std, gray_on_rgb}) {
    auto r = convert("conv_dense_relu", o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code(), ErrorCode::kInvalidArgument) << r.error().message();
  }
}

TEST(OnnxFusion, BatchNormFoldsAndReluSixFusesIntoConvs) {
  for (const char* name : {"mobilenetv2_blocks", "mobilenetv2_blocks_opset17"}) {
    SCOPED_TRACE(name);
    auto converted = convert(name);
    ASSERT_TRUE(converted.ok()) << converted.error().message();
    auto model = Model::load(converted->model);
    ASSERT_TRUE(model.ok());
    EXPECT_EQ(count_ops(**model, OpType::kConv2D), 11u);
    EXPECT_EQ(count_ops(**model, OpType::kAdd), 2u);  // the two residuals, no BN shift
    EXPECT_EQ(count_ops(**model, OpType::kMul), 0u);  // no BN scale
    EXPECT_EQ(count_ops(**model, OpType::kClamp), 0u);
    EXPECT_EQ((*model)->graph().operators.size(), 16u);
  }
}

TEST(OnnxFusion, ZeroPadBecomesConvPaddingOtherPadsStay) {
  auto converted = convert("pad");
  ASSERT_TRUE(converted.ok()) << converted.error().message();
  auto model = Model::load(converted->model);
  ASSERT_TRUE(model.ok());
  // ZeroPad2d feeds a conv (folded); the 0.5-valued pad and the channel pad remain.
  EXPECT_EQ(count_ops(**model, OpType::kPad), 2u);
  const Operator& first = (*model)->graph().operators[0];
  ASSERT_EQ(first.type, OpType::kConv2D);
  const Conv2DParams& p = first.get<Conv2DParams>();
  EXPECT_EQ(p.pad_left, 1);
  EXPECT_EQ(p.pad_right, 2);
  EXPECT_EQ(p.pad_top, 0);
  EXPECT_EQ(p.pad_bottom, 1);
}

}  // namespace
}  // namespace tlvlink
