// `tlvlink quantize` and `tlvlink quantize-sweep` through the built binary: exit codes 0/1/2,
// --help, every calibration source (a simulated Touch100k set, the extreme set, an image folder),
// mixed precision on the command line, the report files, verify on the written model, NaN
// weights, and the sweep's CSV / JSON / SVG. The float model (gen-reference --dtype fp32, 96 px)
// and the data (`tlvlink sim touch100k`) are generated in this process's temp dir.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <png.h>

#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/model.h"
#include "tlvlink/quantize/model_builder.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

using ::tlvlink::testing::CliRun;

using ::tlvlink::testing::run_tlvlink;

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Shared inputs, made once per test process: fp32 reference encoder (96 px) and a small
// simulated Touch100k set (6 sessions x 4 frames).
class QuantizeCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // mkdtemp: a directory a killed run left under this pid's name must not be reused.
    dir_ = new testing::TempDir("quantize_cli");
    setup_ = run_tlvlink("gen-reference -o " + path("fp32.tlvm") +
                         " --dtype fp32 -r 96 --seed 4 --golden 0");
    if (setup_.exit_code == 0)
      setup_ = run_tlvlink(
          "sim touch100k -o " + path("t100k") +
          " --sessions 6 --frames-per-session 4 --seed 2 --vision-height 24 --vision-width 32");
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override { ASSERT_RUN(setup_, 0); }
  static std::string path(const std::string& leaf) { return *dir_ / leaf; }

  static testing::TempDir* dir_;
  static CliRun setup_;
};
testing::TempDir* QuantizeCli::dir_ = nullptr;
CliRun QuantizeCli::setup_;

// Small counts keep the reference executor's share of each run to a few seconds.
const std::string kCounts = " --calib-count 10 --heldout-count 6 -q";

TEST_F(QuantizeCli, HelpListsTheOptionsAndExitsZero) {
  CliRun r = run_tlvlink("quantize --help");
  EXPECT_RUN(r, 0);
  for (const char* flag :
       {"--calib", "--method", "--keep-float", "--report", "--calib-count", "--weights"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  r = run_tlvlink("quantize-sweep --help");
  EXPECT_RUN(r, 0);
  EXPECT_NE(r.out.find("--models"), std::string::npos);
}

TEST_F(QuantizeCli, BadArgumentsExitTwo) {
  const std::string m = path("fp32.tlvm");
  EXPECT_RUN(run_tlvlink("quantize " + m + " -o " + path("x.tlvm")), 2);  // no --calib
  EXPECT_RUN(run_tlvlink("quantize " + m + " --calib " + path("t100k") + " -o " + path("x.tlvm") +
                         " --method kl"),
             2);
  EXPECT_RUN(run_tlvlink("quantize " + m + " --calib " + path("t100k") + " -o " + path("x.tlvm") +
                         " --keep-float no_such_layer"),
             2);
  EXPECT_RUN(
      run_tlvlink("quantize " + m + " --calib extreme -o " + path("x.tlvm") + " --percentile 20"),
      2);
  EXPECT_RUN(run_tlvlink("quantize " + m + " --calib extreme -o " + path("x.tlvm") +
                         " --calib-split train"),
             2);
  EXPECT_FALSE(fs::exists(path("x.tlvm")));
}

// A calibration set that does not exist is the datasets' one error for it (as in eval and train):
// a failure of the work, exit 1, naming the path.
TEST_F(QuantizeCli, MissingCalibrationSetExitsOne) {
  CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("missing") + " -o " +
                         path("x.tlvm"));
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("x.tlvm")));
}

TEST_F(QuantizeCli, Touch100kSetGivesAVerifiableInt8ModelAndAReport) {
  const std::string out = path("q.tlvm");
  CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("t100k") + " -o " +
                         out + " --report " + path("rep") + kCounts);
  ASSERT_RUN(r, 0);
  EXPECT_NE(r.out.find("touch100k"), std::string::npos);
  EXPECT_NE(r.out.find("per layer"), std::string::npos);
  EXPECT_NE(r.out.find("embedding"), std::string::npos);
  auto model = Model::load_file(out.c_str());
  ASSERT_TRUE(model.ok()) << model.error().message();
  size_t int8_convs = 0;
  for (const Operator& op : (*model)->graph().operators)
    int8_convs +=
        op.type == OpType::kConv2D && (*model)->graph().tensor(op.output).dtype == DType::kInt8;
  EXPECT_GT(int8_convs, 10u);
  EXPECT_EQ((*model)->metadata().golden.size(), 2u);
  EXPECT_NE((*model)->metadata().provenance.quantization.find("percentile"), std::string::npos);
  EXPECT_RUN(run_tlvlink("verify " + out), 0);

  const auto j = nlohmann::json::parse(read_text(fs::path(path("rep")) / "report.json"));
  EXPECT_EQ(j["calibration"]["frames"], 10);
  EXPECT_EQ(j["calibration"]["heldout_frames"], 6);
  EXPECT_GT(j["embedding"]["cosine_mean"].get<double>(), 0.99);
  // Bias correction is on by default: every conv/FC with a bias was measured and corrected.
  EXPECT_NE(r.out.find("bias corr."), std::string::npos) << r.out;
  ASSERT_TRUE(j["bias_correction"].is_object()) << j.dump();
  EXPECT_EQ(j["bias_correction"]["frames"], 10);  // all 10 calibration frames (< 64)
  size_t linear = 0;
  for (const Operator& op : (*model)->graph().operators)
    linear += op.type == OpType::kConv2D || op.type == OpType::kFullyConnected;
  EXPECT_EQ(j["bias_correction"]["layers"].size(), linear);
  for (const auto& l : j["bias_correction"]["layers"])
    EXPECT_GT(l["channels_measured"].get<int>(), 0) << l.dump();
  ASSERT_TRUE(j["layers"].is_array());
  EXPECT_EQ(j["layers"].size(), (*model)->graph().operators.size() - 2);  // minus Q and DQ
  const std::string csv = read_text(fs::path(path("rep")) / "layers.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), static_cast<long>(j["layers"].size()) + 1);
  EXPECT_TRUE(fs::exists(fs::path(path("rep")) / "summary.txt"));

  // The training split only (the sidecar's recorded split: 6 sessions, 1 of them test).
  r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("t100k") + " -o " +
                  path("qt.tlvm") + " --calib-split train" + kCounts);
  ASSERT_RUN(r, 0);
  EXPECT_NE(r.out.find("(train split): 20 frames in 5 groups"), std::string::npos) << r.out;

  // --bias-correction 0 turns it off, and says so.
  r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("t100k") + " -o " +
                  path("q0.tlvm") + " --bias-correction 0 --report " + path("rep0") + kCounts);
  ASSERT_RUN(r, 0);
  EXPECT_NE(r.out.find("bias corr.   off"), std::string::npos) << r.out;
  EXPECT_TRUE(
      nlohmann::json::parse(read_text(fs::path(path("rep0")) / "report.json"))["bias_correction"]
          .is_null());
}

TEST_F(QuantizeCli, KeepFloatFirstAndLastAreReportedWithTheirReason) {
  CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("t100k") + " -o " +
                         path("mixed.tlvm") + " --keep-float first,last --report " + path("rep2") +
                         kCounts);
  ASSERT_RUN(r, 0);
  EXPECT_NE(r.out.find("fp32 layers"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stem (Conv2D): kept fp32 by --keep-float"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("embedding (FullyConnected): kept fp32"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(read_text(fs::path(path("rep2")) / "report.json"));
  EXPECT_EQ(j["operators"]["fp32"], 2);
  EXPECT_RUN(run_tlvlink("verify " + path("mixed.tlvm")), 0);
}

TEST_F(QuantizeCli, ExtremeSetAndEveryMethodWork) {
  for (const char* method : {"minmax", "ema", "percentile", "entropy", "mse"}) {
    CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib extreme -o " +
                           path("e.tlvm") + " --method " + method + kCounts);
    EXPECT_RUN(r, 0);
    EXPECT_NE(r.out.find("extreme set"), std::string::npos) << r.out;
  }
}

TEST_F(QuantizeCli, TouchAndGoAndFeelSetsAreDetectedAndRead) {
  ASSERT_RUN(
      run_tlvlink("sim tag -o " + path("tag") + " --sessions 4 --frames-per-session 3 --seed 5"),
      0);
  ASSERT_RUN(
      run_tlvlink("sim feel -o " + path("feel") + " --objects 3 --grasps-per-object 2 --seed 5"),
      0);
  ASSERT_RUN(run_tlvlink("sim feel -o " + path("feelr") +
                         " --objects 3 --grasps-per-object 2 --seed 5 --repacked"),
             0);
  for (const auto& [dir, format] :
       {std::pair{"tag", "tag "}, {"feel", "feel "}, {"feelr", "feel-repacked "}}) {
    CliRun r =
        run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path(dir) + " -o " +
                    path(std::string(dir) + ".tlvm") + " --calib-count 6 --heldout-count 3 -q");
    EXPECT_RUN(r, 0);
    EXPECT_NE(r.out.find(std::string("data         ") + format), std::string::npos) << r.out;
  }
  // The format can be forced; a wrong one is a data error naming the set.
  EXPECT_RUN(run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("tag") +
                         " --calib-format feel -o " + path("bad.tlvm") + kCounts),
             1);
}

TEST_F(QuantizeCli, SeveralSourcesShareTheCountsAndAreRecorded) {
  ASSERT_RUN(run_tlvlink("sim feel -o " + path("feel2") +
                         " --objects 4 --grasps-per-object 2 --seed 6 --repacked"),
             0);
  CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + path("t100k") +
                         " --calib " + path("feel2") + " -o " + path("two.tlvm") +
                         " --calib-count 7 --heldout-count 4 -q");
  ASSERT_RUN(r, 0);
  const size_t touch = r.out.find("data         touch100k "), feel = r.out.find("feel-repacked ");
  ASSERT_NE(touch, std::string::npos) << r.out;
  ASSERT_NE(feel, std::string::npos) << r.out;
  EXPECT_LT(touch, feel);
  EXPECT_NE(r.out.find("calibration 4 frames", touch), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("calibration 3 frames", feel), std::string::npos) << r.out;
  // The second source's line continues under the first, aligned.
  EXPECT_NE(r.out.find("\n               feel-repacked "), std::string::npos) << r.out;
  CliRun inspect = run_tlvlink("inspect " + path("two.tlvm"));
  ASSERT_RUN(inspect, 0);
  EXPECT_NE(inspect.out.find("\"calibration\":\"touch100k+feel-repacked\",\"frames\":7"),
            std::string::npos)
      << inspect.out;
  // Nine sources are one too many: a usage error naming the limit.
  std::string nine;
  for (int i = 0; i < 9; ++i) nine += " --calib extreme";
  r = run_tlvlink("quantize " + path("fp32.tlvm") + nine + " -o " + path("nine.tlvm") + kCounts);
  EXPECT_RUN(r, 2);
  EXPECT_NE(r.out.find("1..8"), std::string::npos) << r.out;
  // --calib takes one path: the model positional after it is still the model.
  EXPECT_RUN(run_tlvlink("quantize --calib extreme " + path("fp32.tlvm") + " -o " +
                         path("order.tlvm") + kCounts),
             0);
}

TEST_F(QuantizeCli, ImageFolderOfPpmJpegAndPng) {
  const fs::path images = path("images");
  fs::create_directories(images / "sessionA");
  fs::create_directories(images / "sessionB");
  for (int i = 0; i < 4; ++i) {
    tools::Image img{120, 100, 3,
                     quantize::synthetic_touch_frame(100, 120, static_cast<uint64_t>(i))};
    ASSERT_TRUE(
        tools::write_pnm((images / "sessionA" / ("f" + std::to_string(i) + ".ppm")).string(), img)
            .ok());
    ASSERT_TRUE(tools::write_jpeg(
                    (images / "sessionB" / ("f" + std::to_string(i) + ".jpg")).string(), img, 90)
                    .ok());
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = 120;
    png.height = 100;
    png.format = PNG_FORMAT_RGB;
    ASSERT_NE(png_image_write_to_file(&png, (images / ("top" + std::to_string(i) + ".png")).c_str(),
                                      0, img.pixels.data(), 0, nullptr),
              0);
  }
  CliRun r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + images.string() + " -o " +
                         path("img.tlvm") + " --calib-count 6 --heldout-count 2 -q");
  ASSERT_RUN(r, 0);
  EXPECT_NE(r.out.find("images"), std::string::npos);
  EXPECT_NE(r.out.find("calibration 6 frames"), std::string::npos) << r.out;
  // A corrupt image is skipped and counted, not fatal.
  std::ofstream(images / "sessionA" / "broken.jpg") << "not a jpeg";
  r = run_tlvlink("quantize " + path("fp32.tlvm") + " --calib " + images.string() + " -o " +
                  path("img2.tlvm") + " --calib-count 12 --heldout-count 0 -q");
  EXPECT_RUN(r, 0);
}

TEST_F(QuantizeCli, NanWeightsFailNamingTheTensor) {
  quantize::ModelBuilder b;
  const int32_t x = b.add_activation("x", DType::kFloat32, {1, 96, 96, 3});
  const std::vector<float> w = {1.0f, std::nanf(""), 0.5f};
  const int32_t wt = b.add_constant<float>("stem.weights", {1, 1, 1, 3}, w);
  const int32_t y = b.add_activation("y", DType::kFloat32, {1, 96, 96, 1});
  b.add_op(OpType::kConv2D, "stem", {x, wt, kNoTensor}, y, Conv2DParams{});
  b.set_inputs({x});
  b.set_outputs({y});
  const std::vector<std::byte> file = b.finish();
  std::ofstream(path("nan.tlvm"), std::ios::binary)
      .write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  CliRun r = run_tlvlink("quantize " + path("nan.tlvm") + " --calib extreme -o " + path("n.tlvm") +
                         kCounts);
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("stem.weights"), std::string::npos) << r.out;
}

TEST_F(QuantizeCli, AnInt8ModelIsNotQuantizedAgain) {
  ASSERT_RUN(run_tlvlink("quantize " + path("fp32.tlvm") + " --calib extreme -o " +
                         path("once.tlvm") + kCounts),
             0);
  CliRun r = run_tlvlink("quantize " + path("once.tlvm") + " --calib extreme -o " +
                         path("twice.tlvm") + kCounts);
  EXPECT_RUN(r, 1);
  EXPECT_NE(r.out.find("already"), std::string::npos) << r.out;
}

TEST_F(QuantizeCli, SweepWritesOneRowPerVariantAndThreadCount) {
  ASSERT_RUN(run_tlvlink("gen-reference -o " + path("fp32_112.tlvm") +
                         " --dtype fp32 -r 112 --seed 4 --golden 0"),
             0);
  CliRun r = run_tlvlink("quantize-sweep --models " + path("fp32.tlvm") + "," +
                         path("fp32_112.tlvm") + " --calib " + path("t100k") + " -o " +
                         path("sweep") + " --methods minmax,mse --threads 1,2 --runs 3 --warmup 1" +
                         " --keep-float first,last" + kCounts);
  ASSERT_RUN(r, 0);
  // 2 models x (fp32, per-channel minmax without bias correction, per-tensor minmax, per-channel
  // minmax, per-channel mse, mixed) x 2 threads.
  constexpr long kRows = 2 * 6 * 2;
  const std::string csv = read_text(fs::path(path("sweep")) / "sweep.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), kRows + 1);
  const auto j = nlohmann::json::parse(read_text(fs::path(path("sweep")) / "sweep.json"));
  ASSERT_EQ(j["rows"].size(), static_cast<size_t>(kRows));
  EXPECT_EQ(j["calibration"]["data"], nlohmann::json::array({path("t100k")}));  // one per --calib
  for (const auto& row : j["rows"]) {
    EXPECT_GT(row["latency_median_ms"].get<double>(), 0.0);
    EXPECT_GT(row["cosine_mean"].get<double>(), 0.99);
  }
  const std::string svg = read_text(fs::path(path("sweep")) / "sweep.svg");
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("int8 per-channel mse"), std::string::npos);
  // The mixed row (calibrated with the first method, minmax) keeps two layers in fp32.
  size_t mixed = 0;
  for (const auto& row : j["rows"]) {
    if (row["variant"] != "int8 per-channel minmax + fp32 first,last") continue;
    ++mixed;
    EXPECT_EQ(row["fp32_ops"].get<int>(), 2) << row.dump();
  }
  EXPECT_EQ(mixed, 4u);
  // Every int8 row but the one named so is bias-corrected on the calibration frames.
  for (const auto& row : j["rows"]) {
    const bool plain = row["variant"] == "int8 per-channel minmax without bias correction";
    const bool int8 = row["precision"] == "int8";
    EXPECT_EQ(row["bias_correction_frames"].get<int>(), int8 && !plain ? 10 : 0) << row.dump();
  }
  EXPECT_RUN(run_tlvlink("quantize-sweep --models " + path("nope.tlvm") + " --calib extreme -o " +
                         path("s2")),
             2);
}

}  // namespace
}  // namespace tlvlink
