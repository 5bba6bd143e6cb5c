// Writes the loader fuzzer's seed corpus: make_fuzz_corpus DIR
// Valid models that together use every operator type in fp32 and in int8 (the all-ops graph,
// a grouped dilated conv), every metadata section (input spec, linear / zero-shot / grasp heads,
// golden pairs) and the 96-px reference encoders, so mutations start deep inside the loader and
// the executors rather than at its first checks. Prints each seed's size (run_fuzz's -max_len
// must cover the largest, or libFuzzer truncates it into an invalid file).
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "model/tiny_models.h"
#include "reference/all_ops_models.h"
#include "tlvlink/quantize/calibrate.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

using quantize::ModelBuilder;
using Seeds = std::vector<std::pair<std::string, std::vector<std::byte>>>;

std::vector<float> wave(size_t n, float phase) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = 0.5f * std::sin(phase + 0.9f * static_cast<float>(i));
  return v;
}

// Conv2D with 2 groups of 2 channels and dilation 2 (the all-ops graph has dense and depthwise
// convs only). Int8 through the project's converter, calibrated on two inputs.
Status add_grouped_conv(Seeds& seeds) {
  ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 6, 6, 4});
  const std::vector<float> w = wave(4 * 3 * 3 * 2, 0.3f), bias = wave(4, 1.1f);
  const int32_t wt = b.add_constant<float>("grouped.w", {4, 3, 3, 2}, w);
  const int32_t bt = b.add_constant<float>("grouped.b", {4}, bias);
  const int32_t y = b.add_activation("grouped.out", DType::kFloat32, {1, 6, 6, 4});
  b.add_op(OpType::kConv2D, "grouped", {x, wt, bt}, y,
           Conv2DParams{3, 3, 1, 1, 2, 2, 2, 2, 2, 2, 2, Activation::kRelu});
  b.set_inputs({x});
  b.set_outputs({y});
  seeds.emplace_back("grouped_conv_fp32.tlvm", b.finish());
  TLV_ASSIGN_OR_RETURN(auto fp32, Model::load(seeds.back().second));
  const std::vector<std::vector<float>> inputs{wave(6 * 6 * 4, 0), wave(6 * 6 * 4, 2)};
  TLV_ASSIGN_OR_RETURN(auto ranges, quantize::collect_ranges(*fp32, inputs));
  TLV_ASSIGN_OR_RETURN(ModelBuilder int8, quantize::convert_to_int8(*fp32, ranges));
  seeds.emplace_back("grouped_conv_int8.tlvm", int8.finish());
  return {};
}

// Every metadata section on the tiny int8 model (embedding dimension 2, input [1,8,8,3]).
std::vector<std::byte> tiny_with_metadata() {
  testing::TinyInt8Model m;
  m.tweak = [](ModelBuilder& b) {
    auto& md = b.metadata();
    md.input.height = md.input.width = 8;
    md.input.crop_w = md.input.crop_h = 6;
    md.input.mean = {0.5f, 0.5f, 0.5f};
    md.input.std = {0.25f, 0.25f, 0.25f};
    md.linear_heads.push_back({"hard_soft", {"hard", "soft"}, {1, 2, 3, 4}, {0, 0}});
    md.zero_shot_heads.push_back(
        {"material", {"wood", "metal"}, "a photo of {}", {1, 0, 0, 1}, 50});
    md.has_grasp_head = true;
    md.grasp_head = {"grasp", "finger0.before,finger0.during", {0.5f, -1, 2, 0.25f}, 0.1f};
    md.golden.push_back({std::vector<std::byte>(8 * 8 * 3 * 4), std::vector<std::byte>(2 * 4)});
  };
  return m.build();
}

// The reference encoders at the smallest resolution and embedding: the weights do not shrink
// with resolution, golden pairs do.
Status add_encoders(Seeds& seeds) {
  for (auto dtype : {quantize::EncoderDType::kFloat32, quantize::EncoderDType::kInt8}) {
    quantize::ReferenceEncoderOptions o;
    o.resolution = quantize::kMinEncoderResolution;
    o.embedding_dim = 8;
    o.dtype = dtype;
    o.calibration_frames = 2;
    o.golden_pairs = 1;
    o.preprocess = quantize::deployment_preprocessor();
    TLV_ASSIGN_OR_RETURN(auto enc, quantize::build_reference_encoder(o));
    const bool int8 = dtype == quantize::EncoderDType::kInt8;
    seeds.emplace_back(int8 ? "encoder_r96_int8.tlvm" : "encoder_r96_fp32.tlvm",
                       std::move(enc.file));
  }
  return {};
}

Status make_seeds(Seeds& seeds) {
  testing::TinyInt8Model plain, stride2;
  stride2.conv.stride_h = stride2.conv.stride_w = 2;
  stride2.conv_output_shape = {1, 4, 4, 4};
  seeds.emplace_back("tiny_int8.tlvm", plain.build());
  seeds.emplace_back("tiny_int8_stride2.tlvm", stride2.build());
  seeds.emplace_back("tiny_int8_metadata.tlvm", tiny_with_metadata());
  seeds.emplace_back("all_ops_fp32.tlvm", reference_test::all_ops_model(false));
  seeds.emplace_back("all_ops_int8.tlvm", reference_test::all_ops_model(true));
  TLV_TRY(add_grouped_conv(seeds));
  return add_encoders(seeds);
}

bool write(const std::string& path, const std::vector<std::byte>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace
}  // namespace tlvlink

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_fuzz_corpus DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  tlvlink::Seeds seeds;
  if (const tlvlink::Status s = tlvlink::make_seeds(seeds); !s.ok()) {
    std::fprintf(stderr, "make_fuzz_corpus: %s\n", s.error().message());
    return 1;
  }
  for (const auto& [name, bytes] : seeds) {
    // A seed the loader rejects would only seed the loader's first checks: a generator bug.
    if (auto m = tlvlink::Model::load(bytes); !m.ok()) {
      std::fprintf(stderr, "make_fuzz_corpus: %s does not load: %s\n", name.c_str(),
                   m.error().message());
      return 1;
    }
    if (!tlvlink::write(dir + "/" + name, bytes)) {
      std::fprintf(stderr, "make_fuzz_corpus: cannot write %s/%s\n", dir.c_str(), name.c_str());
      return 1;
    }
    std::printf("%-26s %7zu bytes\n", name.c_str(), bytes.size());
  }
  return 0;
}
