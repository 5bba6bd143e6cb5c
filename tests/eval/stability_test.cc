// The stability suite (tlvlink/eval/stability.h) as a measuring tool, on a seeded reference
// encoder: which paths it measures, its statistics, real frames, errors. The shipped model's
// stability itself is guarded by shipped_stability_test.cc.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.h"
#include "tlvlink/eval/stability.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/file.h"
#include "tlvlink/quantize/frames.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink::eval {
namespace {

std::unique_ptr<Model> reference_model(std::vector<std::byte>& file) {
  quantize::ReferenceEncoderOptions o;
  o.dtype = quantize::EncoderDType::kFloat32;
  o.resolution = 96;
  o.seed = 5;
  o.embedding_dim = 32;
  o.preprocess = quantize::deployment_preprocessor();
  auto enc = quantize::build_reference_encoder(o);
  EXPECT_TRUE(enc.ok()) << enc.error().message();
  file = enc->file;
  auto m = Model::load(file);
  EXPECT_TRUE(m.ok()) << m.error().message();
  return m.ok() ? std::move(*m) : nullptr;
}

const PathStability* find(const StabilityReport& r, const std::string& source,
                          const std::string& path) {
  for (const PathStability& p : r.paths) {
    if (p.source == source && p.path == path) return &p;
  }
  return nullptr;
}

TEST(Stability, MeasuresEverySimulatedPathOfEveryScene) {
  std::vector<std::byte> file;
  auto model = reference_model(file);
  ASSERT_TRUE(model);
  StabilityOptions o;
  o.scenes = 8;
  auto r = measure_stability(*model, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->scenes, 8);
  EXPECT_EQ(r->real_frames, 0);
  EXPECT_EQ(r->real_note, "no real frames given");
  int64_t live = 0;
  for (const char* path : {"jpeg-q95", "jpeg-q90", "jpeg-q75"}) {
    const PathStability* p = find(*r, "simulated", path);
    ASSERT_NE(p, nullptr) << path;
    EXPECT_EQ(p->n, 8);
    EXPECT_LE(p->cos_min, p->cos_p05);
    EXPECT_LE(p->cos_p05, p->cos_median);
    EXPECT_LE(p->cos_median, 1.0 + 1e-9);
    EXPECT_GE(p->cos_min, -1.0 - 1e-9);
    EXPECT_NE(p->worst.find("scene "), std::string::npos);
  }
  for (const char* sensor : {"live gelsight-mini", "live digit"}) {
    if (const PathStability* p = find(*r, "simulated", sensor)) live += p->n;
  }
  EXPECT_EQ(live, 8);  // every scene through its own sensor's live path
  // JPEG q75 is lossy: some embedding moves (a measuring tool that always said 1 would pass).
  EXPECT_LT(find(*r, "simulated", "jpeg-q75")->cos_min, 1.0);
  const auto j = nlohmann::json::parse(stability_json(*r));
  EXPECT_EQ(j.at("paths").size(), r->paths.size());
  EXPECT_EQ(j.at("targets").at("min_cosine"), kStabilityMinCosine);
  EXPECT_NE(format_stability(*r).find("jpeg-q75"), std::string::npos);
}

TEST(Stability, RealFramesAreReencodedAndShifted) {
  std::vector<std::byte> file;
  auto model = reference_model(file);
  ASSERT_TRUE(model);
  testing::TempDir dir;
  image::Image frame{64, 48, 3, std::vector<uint8_t>(64 * 48 * 3)};
  for (size_t i = 0; i < frame.pixels.size(); ++i)
    frame.pixels[i] = static_cast<uint8_t>(i * 7 % 251);
  auto jpeg = image::encode_jpeg(frame, 92);
  ASSERT_TRUE(jpeg.ok());
  std::filesystem::create_directories(dir.path() + "/a/b");
  ASSERT_TRUE(tools::write_file(dir.path() + "/a/b/f.jpg", std::as_bytes(std::span(*jpeg))).ok());
  ASSERT_TRUE(tools::write_file(dir.path() + "/notes.txt", std::as_bytes(std::span("x", 1))).ok());
  StabilityOptions o;
  o.scenes = 0;
  o.real_frames_dir = dir.path();
  auto r = measure_stability(*model, o);
  ASSERT_TRUE(r.ok()) << r.error().message();
  EXPECT_EQ(r->real_frames, 1);
  for (const char* path : {"jpeg-q95", "jpeg-q90", "jpeg-q75", "+3 DN", "-3 DN"}) {
    const PathStability* p = find(*r, "real", path);
    ASSERT_NE(p, nullptr) << path;
    EXPECT_EQ(p->n, 1);
    EXPECT_EQ(p->worst, "a/b/f.jpg");
  }
  o.real_frames_dir = dir.path() + "/missing";
  auto missing = measure_stability(*model, o);
  ASSERT_TRUE(missing.ok());
  EXPECT_NE(missing->real_note.find("is not there"), std::string::npos);
  EXPECT_FALSE(missing->meets_target());  // nothing measured is no pass
}

TEST(Stability, TargetsAreTheIssuesAndTrustedHeadsOnly) {
  PathStability p;
  p.n = 10;
  p.cos_min = 0.975;
  p.heads = {{"material", true, 96, 100}, {"zero_shot", false, 10, 100}};
  EXPECT_TRUE(p.meets_target());  // an untrusted head is not held to the agreement target
  p.heads[0].same = 94;
  EXPECT_FALSE(p.meets_target());
  p.heads[0].same = 96;
  p.cos_min = 0.969;
  EXPECT_FALSE(p.meets_target());
  std::vector<std::byte> file;
  auto model = reference_model(file);
  ASSERT_TRUE(model);
  StabilityOptions o;
  o.scenes = -1;
  EXPECT_EQ(measure_stability(*model, o).error().code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace tlvlink::eval
