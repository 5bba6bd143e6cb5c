// `tlvlink` end to end, through the real binary: gen-reference -> inspect -> infer (both
// executors) -> verify -> bench, plus bad model files (exit 1) and bad arguments (exit 2).

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <png.h>
#include <nlohmann/json.hpp>

#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/pnm.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

using ::tlvlink::testing::CliRun;
using ::tlvlink::tools::NpyArray;

using ::tlvlink::testing::run_tlvlink;

// Models come from the CTest fixtures cli.gen_reference_{fp32,int8} (96 px, seed 3, run once
// per ctest invocation); every test writes its own files into a private directory.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* m : {"fp32.tlvm", "int8.tlvm"}) {
      const fs::path src = fs::path(TLVLINK_CLI_MODELS) / m;
      if (!fs::exists(src))
        FAIL() << src << " missing: run through ctest (fixtures cli.gen_reference_*)";
      fs::copy_file(src, dir_ / m, fs::copy_options::overwrite_existing);
    }
  }
  std::string path(const std::string& leaf) const { return (dir_ / leaf).string(); }

  ::tlvlink::testing::TempDir tmp_{"cli"};  // a fresh directory, removed with the fixture
  fs::path dir_ = tmp_.path();
};

TEST_F(Cli, GenReferenceWritesAModelThatLoads) {
  CliRun gen =
      run_tlvlink("gen-reference -o " + path("g.tlvm") + " --dtype fp32 -r 96 --golden 1 --seed 9");
  EXPECT_RUN(gen, 0);
  EXPECT_NE(gen.out.find("MMAC"), std::string::npos) << gen.out;
  EXPECT_RUN(run_tlvlink("inspect " + path("g.tlvm")), 0);
}

TEST_F(Cli, GenFramesWritesSeededFramesThatInferAccepts) {
  EXPECT_RUN(run_tlvlink("gen-frames -o " + path("f") + " -n 2 --height 60 --width 80 --seed 5"),
             0);
  auto a = tools::read_pnm(path("f/frame_0000.ppm"));
  auto b = tools::read_pnm(path("f/frame_0001.ppm"));
  ASSERT_TRUE(a.ok()) << a.error().message();
  ASSERT_TRUE(b.ok()) << b.error().message();
  EXPECT_EQ(a->width, 80);
  EXPECT_EQ(a->height, 60);
  EXPECT_EQ(a->channels, 3);
  EXPECT_NE(a->pixels, b->pixels) << "frames with different seeds must differ";
  // Same seed, same bytes (the demo and tests rely on it).
  EXPECT_RUN(run_tlvlink("gen-frames -o " + path("g") + " -n 1 --height 60 --width 80 --seed 5"),
             0);
  auto again = tools::read_pnm(path("g/frame_0000.ppm"));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->pixels, a->pixels);
  // A frame of another size goes through the model's preprocessing (resize) into infer.
  EXPECT_RUN(run_tlvlink("infer " + path("int8.tlvm") + " --input " + path("f/frame_0000.ppm")), 0);
  EXPECT_RUN(run_tlvlink("gen-frames -o " + path("h") + " --width 0"), 2);
  EXPECT_RUN(run_tlvlink("gen-frames -o " + path("h") + " --height 5000"), 2);
}

TEST_F(Cli, InspectPrintsTablesAndJson) {
  CliRun text = run_tlvlink("inspect " + path("int8.tlvm"));
  EXPECT_RUN(text, 0);
  for (const char* s : {"random-reference", "per-channel axis 0", "Quantize", "Dequantize",
                        "totals:", "MMAC", "material (20)"}) {
    EXPECT_NE(text.out.find(s), std::string::npos) << "missing '" << s << "' in\n" << text.out;
  }
  CliRun json = run_tlvlink("inspect --json " + path("fp32.tlvm"));
  EXPECT_RUN(json, 0);
  const auto j = nlohmann::json::parse(json.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(j.is_discarded()) << json.out.substr(0, 500);
  const double mmac = j["totals"]["mmac"].get<double>();
  EXPECT_GT(mmac, 10.0);  // 96 px: ~21 MMAC
  EXPECT_LT(mmac, 30.0);
  EXPECT_EQ(j["metadata"]["input"]["height"].get<int>(), 96);
  EXPECT_GT(j["operators"].size(), 20u);
}

TEST_F(Cli, InferOnImagesAndTensorsWithBothExecutors) {
  // 4:3, not the model's 96x96 (the resize is exercised); infer refuses frames of other aspects
  // that no known sensor makes (tests/capture/still_frame_test.cc).
  tools::Image img{120, 90, 3, {}};
  for (int i = 0; i < 120 * 90 * 3; ++i) img.pixels.push_back(static_cast<uint8_t>((i * 7) % 251));
  ASSERT_TRUE(tools::write_pnm(path("frame.ppm"), img).ok());
  std::vector<float> x(96 * 96 * 3, 0.25f);
  ASSERT_TRUE(
      tools::write_npy(path("x.npy"), tools::NpyArray::from<float>({1, 96, 96, 3}, x)).ok());
  for (const char* model : {"fp32.tlvm", "int8.tlvm"}) {
    for (const char* exec : {"xnnpack", "reference"}) {
      SCOPED_TRACE(std::string(model) + " " + exec);
      CliRun summary = run_tlvlink("infer " + path(model) + " --input " + path("frame.ppm") +
                                   " --executor " + exec);
      EXPECT_RUN(summary, 0);
      EXPECT_NE(summary.out.find("head material"), std::string::npos) << summary.out;
      const std::string out = path(std::string(exec) + "_" + model + ".npy");
      CliRun written = run_tlvlink("infer " + path(model) + " -i " + path("x.npy") + " -o " + out +
                                   " -e " + exec + " -t 2");
      EXPECT_RUN(written, 0);
      auto y = tools::read_npy(out);
      ASSERT_TRUE(y.ok()) << y.error().message();
      EXPECT_EQ(y->dtype, DType::kFloat32);
      EXPECT_EQ(y->shape, (std::vector<int64_t>{1, 128}));
    }
  }
}

// A camera's JPEG (and a PNG) feed the model like the PPM holding the same pixels: preprocessing
// is shared, so the only difference is JPEG's loss. A cut-off JPEG is an error naming the file.
TEST_F(Cli, InferTakesJpegAndPngFramesAndRejectsTruncatedOnes) {
  tools::Image img{160, 120, 3, {}};  // width, height
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c) img.pixels.push_back(static_cast<uint8_t>(60 + x / 2 + c * 20));
  ASSERT_TRUE(tools::write_pnm(path("smooth.ppm"), img).ok());
  ASSERT_TRUE(tools::write_jpeg(path("smooth.jpg"), img, 95).ok());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = 160;
  png.height = 120;
  png.format = PNG_FORMAT_RGB;
  ASSERT_NE(
      png_image_write_to_file(&png, path("smooth.png").c_str(), 0, img.pixels.data(), 0, nullptr),
      0);
  for (const char* name : {"smooth.ppm", "smooth.jpg", "smooth.png"}) {
    EXPECT_RUN(run_tlvlink("infer " + path("fp32.tlvm") + " -i " + path(name) + " -o " +
                           path(std::string(name) + ".npy")),
               0);
  }
  auto ppm = tools::read_npy(path("smooth.ppm.npy"));
  auto jpg = tools::read_npy(path("smooth.jpg.npy"));
  auto pngo = tools::read_npy(path("smooth.png.npy"));
  ASSERT_TRUE(ppm.ok() && jpg.ok() && pngo.ok());
  EXPECT_EQ(pngo->data, ppm->data);  // lossless: bit-identical embeddings
  // q95 JPEG of a smooth ramp moves pixels by ~1 DN: embeddings stay within 5 % of their scale.
  const auto* a = reinterpret_cast<const float*>(ppm->data.data());
  const auto* b = reinterpret_cast<const float*>(jpg->data.data());
  float scale = 0, diff = 0;
  for (size_t i = 0; i < ppm->data.size() / 4; ++i) {
    scale = std::max(scale, std::abs(a[i]));
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  EXPECT_LE(diff, 0.05f * scale);

  std::ifstream in(path("smooth.jpg"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(path("cut.jpg"), std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  CliRun cut = run_tlvlink("infer " + path("fp32.tlvm") + " -i " + path("cut.jpg"));
  EXPECT_RUN(cut, 1);
  EXPECT_NE(cut.out.find(path("cut.jpg")), std::string::npos) << cut.out;
}

// A uint8 .npy image ([H,W,3] as numpy holds an RGB frame, or [1,H,W,3]) takes the PPM's path
// through preprocessing: bit-identical outputs on both models. A uint8 array that is no image
// (wrong rank, channels or batch) and an image-shaped array of another dtype are bad data: exit 1,
// the message naming the file and what is wrong with it.
TEST_F(Cli, InferTakesUint8NpyImagesLikeTheSamePpm) {
  constexpr int32_t kH = 90, kW = 120;  // not the model's 96x96 (4:3): the resize is exercised too
  tools::Image img{kW, kH, 3, {}};
  for (int i = 0; i < kH * kW * 3; ++i) img.pixels.push_back(static_cast<uint8_t>((i * 11) % 241));
  const std::span<const uint8_t> px(img.pixels);
  ASSERT_TRUE(tools::write_pnm(path("img.ppm"), img).ok());
  ASSERT_TRUE(tools::write_npy(path("img.npy"), NpyArray::from<uint8_t>({kH, kW, 3}, px)).ok());
  ASSERT_TRUE(tools::write_npy(path("img1.npy"), NpyArray::from<uint8_t>({1, kH, kW, 3}, px)).ok());
  for (const char* model : {"fp32.tlvm", "int8.tlvm"}) {
    SCOPED_TRACE(model);
    auto infer = [&](const std::string& input) {
      const std::string out = path(input + "." + model + ".npy");
      EXPECT_RUN(run_tlvlink("infer " + path(model) + " --input " + path(input) + " -o " + out), 0);
      return tools::read_npy(out);
    };
    auto from_ppm = infer("img.ppm");
    auto from_npy = infer("img.npy");
    auto from_batched = infer("img1.npy");
    ASSERT_TRUE(from_ppm.ok() && from_npy.ok() && from_batched.ok());
    EXPECT_EQ(from_ppm->shape, (std::vector<int64_t>{1, 128}));
    EXPECT_EQ(from_npy->dtype, from_ppm->dtype);
    EXPECT_EQ(from_npy->shape, from_ppm->shape);
    EXPECT_EQ(from_npy->data, from_ppm->data);
    EXPECT_EQ(from_batched->data, from_ppm->data);
  }

  struct Bad {
    std::string file;
    NpyArray array;
    int exit_code;
    std::string message;
  };
  const size_t n = img.pixels.size();
  const std::vector<uint8_t> two(2 * n, 9);  // two frames, or one of 4 channels (and spare)
  const std::vector<int8_t> as_int8(n, 9);
  const std::vector<float> as_float(n, 9.0f);
  const Bad bad[] = {
      {"gray2d.npy", NpyArray::from<uint8_t>({kH, kW}, px.first(n / 3)), 1,
       "uint8 image shape (90, 120); expected [H,W,C] or [1,H,W,C]"},
      {"rank5.npy", NpyArray::from<uint8_t>({1, 1, kH, kW, 3}, px), 1,
       "uint8 image shape (1, 1, 90, 120, 3); expected [H,W,C] or [1,H,W,C]"},
      {"batch2.npy", NpyArray::from<uint8_t>({2, kH, kW, 3}, std::span(two)), 1,
       "uint8 image shape (2, 90, 120, 3); expected [H,W,C] or [1,H,W,C]"},
      {"rgba.npy", NpyArray::from<uint8_t>({kH, kW, 4}, std::span(two).first(n / 3 * 4)), 1,
       "uint8 image shape (90, 120, 4); need 1 or 3 channels"},
      {"int8.npy", NpyArray::from<int8_t>({kH, kW, 3}, std::span(as_int8)), 1,
       "int8 tensor of shape (90, 120, 3) does not match model input 'input' float32"},
      {"float.npy", NpyArray::from<float>({kH, kW, 3}, std::span(as_float)), 1,
       "float32 tensor of shape (90, 120, 3) does not match model input 'input' float32"},
  };
  for (const Bad& b : bad) {
    SCOPED_TRACE(b.file);
    ASSERT_TRUE(tools::write_npy(path(b.file), b.array).ok());
    CliRun r = run_tlvlink("infer " + path("fp32.tlvm") + " --input " + path(b.file));
    EXPECT_RUN(r, b.exit_code);
    EXPECT_NE(r.out.find(path(b.file)), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(b.message), std::string::npos) << r.out;
    if (b.array.dtype != DType::kUInt8) {
      EXPECT_NE(r.out.find("images: uint8 [H,W,C] or [1,H,W,C]"), std::string::npos) << r.out;
    }
  }
}

TEST_F(Cli, InferComparesBothExecutorsWithTheVerifyTolerances) {
  tools::Image img{240, 320, 3, {}};
  for (int i = 0; i < 240 * 320 * 3; ++i)
    img.pixels.push_back(static_cast<uint8_t>((i * 13) % 253));
  ASSERT_TRUE(tools::write_pnm(path("cmp.ppm"), img).ok());
  CliRun f =
      run_tlvlink("infer " + path("fp32.tlvm") + " -i " + path("cmp.ppm") + " --compare-executors");
  EXPECT_RUN(f, 0);
  EXPECT_NE(f.out.find("xnnpack vs reference executor"), std::string::npos) << f.out;
  EXPECT_NE(f.out.find("1e-4 x max|reference|): PASS"), std::string::npos) << f.out;
  CliRun q = run_tlvlink("infer " + path("int8.tlvm") + " -i " + path("cmp.ppm") +
                         " -e reference --compare-executors -o " + path("cmp.npy"));
  EXPECT_RUN(q, 0);
  EXPECT_NE(q.out.find("reference vs xnnpack executor"), std::string::npos) << q.out;
  EXPECT_NE(q.out.find(" LSB), tolerance"), std::string::npos) << q.out;
  EXPECT_NE(q.out.find("1 LSB of the dequantized int8 output): PASS"), std::string::npos) << q.out;
}

TEST_F(Cli, InferRejectsMismatchedInputsNamingBothShapes) {
  std::vector<float> x(64 * 64 * 3, 0.0f);
  ASSERT_TRUE(
      tools::write_npy(path("small.npy"), tools::NpyArray::from<float>({1, 64, 64, 3}, x)).ok());
  CliRun r = run_tlvlink("infer " + path("fp32.tlvm") + " --input " + path("small.npy"));
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("(1, 64, 64, 3)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[1, 96, 96, 3]"), std::string::npos) << r.out;
  std::ofstream(path("junk.npy")) << "\x93NUMPY\x01\x00\xff\xff{";
  CliRun junk = run_tlvlink("infer " + path("fp32.tlvm") + " --input " + path("junk.npy"));
  EXPECT_RUN(junk, 1);
  EXPECT_NE(junk.out.find(path("junk.npy")), std::string::npos) << junk.out;
}

TEST_F(Cli, VerifyPassesOnBothExecutors) {
  for (const char* model : {"fp32.tlvm", "int8.tlvm"}) {
    for (const char* exec : {"xnnpack", "reference"}) {
      CliRun r = run_tlvlink("verify " + path(model) + " --executor " + exec);
      EXPECT_RUN(r, 0);
      EXPECT_NE(r.out.find("PASS"), std::string::npos) << r.out;
    }
  }
  CliRun none =
      run_tlvlink("gen-reference -o " + path("nogold.tlvm") + " --dtype fp32 -r 96 --golden 0");
  EXPECT_RUN(none, 0);
  CliRun r = run_tlvlink("verify " + path("nogold.tlvm"));
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("no golden pairs"), std::string::npos) << r.out;
}

// keygen -> sign -> verify --public-key; the secret key file is 0600 and never overwritten;
// a file from before the trailer is refused naming `upgrade`, which makes it load again.
TEST_F(Cli, KeygenSignVerifyAndUpgrade) {
  EXPECT_RUN(run_tlvlink("keygen -o " + path("k")), 0);
  EXPECT_EQ(fs::status(path("k.key")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_RUN(run_tlvlink("keygen -o " + path("k")), 1);  // exists: never overwritten
  EXPECT_RUN(run_tlvlink("keygen -o " + path("other")), 0);
  CliRun unsigned_run =
      run_tlvlink("verify " + path("int8.tlvm") + " --public-key " + path("k.pub"));
  EXPECT_RUN(unsigned_run, 1);
  EXPECT_NE(unsigned_run.out.find("not signed"), std::string::npos) << unsigned_run.out;
  EXPECT_RUN(run_tlvlink("sign " + path("int8.tlvm") + " --key " + path("k.key") + " -o " +
                         path("signed.tlvm")),
             0);
  CliRun good = run_tlvlink("verify " + path("signed.tlvm") + " --public-key " + path("k.pub"));
  EXPECT_RUN(good, 0);
  EXPECT_NE(good.out.find("signature"), std::string::npos) << good.out;
  EXPECT_NE(good.out.find("golden head outputs"), std::string::npos) << good.out;
  CliRun other =
      run_tlvlink("verify " + path("signed.tlvm") + " --public-key " + path("other.pub"));
  EXPECT_RUN(other, 1);
  EXPECT_NE(other.out.find("signed by key"), std::string::npos) << other.out;
  // A secret key is not accepted as a public key, nor the reverse.
  EXPECT_RUN(run_tlvlink("verify " + path("signed.tlvm") + " --public-key " + path("k.key")), 1);
  EXPECT_RUN(run_tlvlink("sign " + path("int8.tlvm") + " --key " + path("k.pub")), 1);
  // Strip the trailer: what a file from before it looks like.
  fs::copy_file(path("int8.tlvm"), path("old.tlvm"));
  fs::resize_file(path("old.tlvm"), fs::file_size(path("int8.tlvm")) - 112);
  CliRun old = run_tlvlink("verify " + path("old.tlvm"));
  EXPECT_RUN(old, 1);
  EXPECT_NE(old.out.find("tlvlink upgrade"), std::string::npos) << old.out;
  EXPECT_RUN(run_tlvlink("upgrade " + path("old.tlvm") + " -o " + path("new.tlvm")), 0);
  EXPECT_RUN(run_tlvlink("verify " + path("new.tlvm")), 0);
}

TEST_F(Cli, BenchReportsTimingsAsTextAndJson) {
  CliRun text = run_tlvlink("bench " + path("int8.tlvm") + " --runs 5 --warmup 1");
  EXPECT_RUN(text, 0);
  for (const char* s : {"median", "p90", "p99", "GMAC/s", "peak RSS", "init"}) {
    EXPECT_NE(text.out.find(s), std::string::npos) << s << "\n" << text.out;
  }
  CliRun json = run_tlvlink("bench " + path("fp32.tlvm") + " --runs 5 --json -e reference");
  EXPECT_RUN(json, 0);
  const auto j = nlohmann::json::parse(json.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << json.out;
  EXPECT_GT(j["median_ms"].get<double>(), 0.0);
  EXPECT_GE(j["p99_ms"].get<double>(), j["median_ms"].get<double>());
  EXPECT_EQ(j["executor"], "reference");
  EXPECT_GT(j["peak_rss_mib"].get<double>(), 0.0);
}

TEST_F(Cli, BadModelFilesExitOneNamingTheProblem) {
  std::ofstream(path("garbage.tlvm")) << "this is not a model";
  CliRun r = run_tlvlink("inspect " + path("garbage.tlvm"));
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find(path("garbage.tlvm")), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("model."), std::string::npos)
      << r.out;  // error code name, e.g. model.malformed
  // A truncated real model.
  const auto size = fs::file_size(path("int8.tlvm"));
  fs::copy_file(path("int8.tlvm"), path("cut.tlvm"), fs::copy_options::overwrite_existing);
  fs::resize_file(path("cut.tlvm"), size / 2);
  const std::string cut = path("cut.tlvm");
  for (const std::string& cmd : {"inspect " + cut, "verify " + cut, "bench " + cut,
                                 "infer " + cut + " --input " + path("x.npy")}) {
    CliRun c = run_tlvlink(cmd);
    EXPECT_RUN(c, 1);
    EXPECT_NE(c.out.find("cut.tlvm"), std::string::npos) << c.out;
  }
  CliRun missing = run_tlvlink("inspect " + path("missing.tlvm"));
  EXPECT_RUN(missing, 1);
}

TEST_F(Cli, BadArgumentsExitTwo) {
  EXPECT_RUN(run_tlvlink(""), 2);
  EXPECT_RUN(run_tlvlink("frobnicate"), 2);
  EXPECT_RUN(run_tlvlink("inspect"), 2);
  EXPECT_RUN(run_tlvlink("inspect a b c"), 2);
  EXPECT_RUN(run_tlvlink("infer " + path("fp32.tlvm")), 2);  // --input is required
  EXPECT_RUN(run_tlvlink("bench " + path("fp32.tlvm") + " --threads 0"), 2);
  EXPECT_RUN(run_tlvlink("bench " + path("fp32.tlvm") + " --runs abc"), 2);
  EXPECT_RUN(run_tlvlink("bench " + path("fp32.tlvm") + " --executor gpu"), 2);
  EXPECT_RUN(run_tlvlink("gen-reference -o x.tlvm --resolution 50"), 2);
  EXPECT_RUN(run_tlvlink("gen-reference -o x.tlvm --dtype fp16"), 2);
  // --help works everywhere and exits 0 with the exit-code footer.
  for (const char* cmd : {"", "inspect ", "infer ", "verify ", "bench ", "gen-reference "}) {
    CliRun h = run_tlvlink(std::string(cmd) + "--help");
    EXPECT_RUN(h, 0);
    EXPECT_NE(h.out.find("Exit codes"), std::string::npos) << h.out;
  }
}

}  // namespace
}  // namespace tlvlink
