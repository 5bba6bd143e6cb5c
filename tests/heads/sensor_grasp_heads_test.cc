// Grasp heads per sensor model (issue 29): the loader reads and validates them, the evaluator
// picks the one for the fingers' sensor model (else the grasp head, fitted on every sensor), and
// their golden outputs are stored and checked like the grasp head's. Older files (none) load as
// before.
#include <cmath>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "model/tiny_models.h"
#include "support/test_models.h"
#include "tlvlink/heads/evaluator.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/verify/golden_heads.h"

namespace tlvlink::testing {
namespace {

constexpr const char* kLayout = "finger0.before,finger0.during";  // 2 x dim 2 = 4 weights

quantize::GraspHeadSpec head(std::vector<float> weight, float bias,
                             std::vector<std::string> sensors) {
  quantize::GraspHeadSpec h{"grasp", kLayout, std::move(weight), bias};
  h.sensors = std::move(sensors);
  return h;
}

// The tiny model (embedding dim 2) with a grasp head, `sensor_heads` and a golden pair.
TinyInt8Model with_sensor_heads(std::vector<quantize::GraspHeadSpec> sensor_heads) {
  TinyInt8Model m;
  m.tweak = [sensor_heads](quantize::ModelBuilder& b) {
    auto& md = b.metadata();
    md.has_grasp_head = true;
    md.grasp_head = head({1, 2, 3, 4}, 0.25f, {});
    md.sensor_grasp_heads = sensor_heads;
    // Golden output: the embedding (1.5, -0.5) as float32.
    std::vector<std::byte> out(2 * sizeof(float));
    const float e[2] = {1.5f, -0.5f};
    std::memcpy(out.data(), e, sizeof(e));
    md.golden.push_back({std::vector<std::byte>(8 * 8 * 3 * 4, std::byte{0}), out});
  };
  return m;
}

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

TEST(SensorGraspHeads, LoadAndTheFingersSensorModelPicksItsHead) {
  auto model = load_model(with_sensor_heads({head({-1, -2, -3, -4}, -0.25f, {"digit"}),
                                             head({0.5f, 0, 0, 0.5f}, 1, {"gelsight-mini"})})
                              .build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  ASSERT_EQ(md.sensor_grasp_heads.size(), 2u);
  EXPECT_EQ(md.sensor_grasp_heads[0].sensors, std::vector<std::string_view>{"digit"});
  EXPECT_EQ(md.sensor_grasp_heads[1].feature_layout, kLayout);
  auto h = heads::HeadEvaluator::create(md);
  ASSERT_TRUE(h.ok()) << h.error().message();
  EXPECT_EQ(h->grasp_head_count(), 3u);
  EXPECT_EQ(h->grasp_head_for("digit"), 1u);
  EXPECT_EQ(h->grasp_head_for("gelsight-mini"), 2u);
  EXPECT_EQ(h->grasp_head_for("9dtact"), 0u) << "a sensor without a head uses the grasp head";
  EXPECT_EQ(h->grasp_head_for(""), 0u);
  // Features (1, 1) and (2, 0): each head's own weights (exact: a few float products).
  const float before[2] = {1, 1}, during[2] = {2, 0};
  const std::span<const float> f[2] = {before, during};
  const float want[3] = {sigmoid(1 + 2 + 6 + 0 + 0.25f), sigmoid(-1 - 2 - 6 - 0 - 0.25f),
                         sigmoid(0.5f + 0 + 0 + 0 + 1)};
  for (size_t k = 0; k < 3; ++k) {
    auto p = h->grasp_probability(f, k);
    ASSERT_TRUE(p.ok()) << p.error().message();
    EXPECT_FLOAT_EQ(*p, want[k]) << "head " << k;
  }
  EXPECT_FALSE(h->grasp_probability(f, 3).ok()) << "head 3 does not exist";
}

TEST(SensorGraspHeads, GoldenOutputsAreStoredPerHeadAndChecked) {
  auto model = load_model(
      with_sensor_heads({head({-1, -2, -3, -4}, -0.25f, {"digit", "digit-360"})}).build());
  ASSERT_NE(model, nullptr);
  const Metadata& md = model->metadata();
  ASSERT_TRUE(md.has_golden_grasp);
  ASSERT_TRUE(md.sensor_grasp_heads[0].has_golden);
  // Feature k reads golden pair k % 1: both features are the embedding (1.5, -0.5).
  EXPECT_FLOAT_EQ(md.golden_grasp, sigmoid(1.5f - 1 + 4.5f - 2 + 0.25f));
  EXPECT_FLOAT_EQ(md.sensor_grasp_heads[0].golden, sigmoid(-1.5f + 1 - 4.5f + 2 - 0.25f));
  auto check = verify::check_golden_heads(*model);
  ASSERT_TRUE(check.ok()) << check.error().message();
  EXPECT_TRUE(check->stored);
  EXPECT_TRUE(check->pass) << check->max_abs_error;
}

TEST(SensorGraspHeads, SurviveAMetadataRewrite) {
  auto model = load_model(with_sensor_heads({head({-1, -2, -3, -4}, -0.25f, {"digit"})}).build());
  ASSERT_NE(model, nullptr);
  const quantize::MetadataSpec spec = quantize::metadata_spec_from(model->metadata());
  ASSERT_EQ(spec.sensor_grasp_heads.size(), 1u);
  EXPECT_EQ(spec.sensor_grasp_heads[0].sensors, std::vector<std::string>{"digit"});
  EXPECT_EQ(spec.sensor_grasp_heads[0].weight, (std::vector<float>{-1, -2, -3, -4}));
}

TEST(SensorGraspHeads, AFileWithoutThemHasTheGraspHeadOnly) {
  auto model = load_model(with_sensor_heads({}).build());
  ASSERT_NE(model, nullptr);
  auto h = heads::HeadEvaluator::create(model->metadata());
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->grasp_head_count(), 1u);
  EXPECT_EQ(h->grasp_head_for("digit"), 0u);
}

TEST(SensorGraspHeads, InconsistentHeadsAreRefusedNamingTheDefect) {
  struct Case {
    const char* what;
    std::vector<quantize::GraspHeadSpec> heads;
    bool drop_grasp_head = false;
    const char* says;
  };
  quantize::GraspHeadSpec other_layout = head({1, 2, 3, 4}, 0, {"digit"});
  other_layout.feature_layout = "finger1.before,finger1.during";
  const Case cases[] = {
      {"another layout", {other_layout}, false, "reads 'finger1.before,finger1.during'"},
      {"no sensor named", {head({1, 2, 3, 4}, 0, {})}, false, "names no sensor model"},
      {"a sensor twice",
       {head({1, 2, 3, 4}, 0, {"digit"}), head({1, 2, 3, 4}, 0, {"digit"})},
       false,
       "'digit' has two sensor grasp heads"},
      {"no grasp head", {head({1, 2, 3, 4}, 0, {"digit"})}, true, "but no grasp head"},
      {"a NaN weight", {head({1, NAN, 3, 4}, 0, {"digit"})}, false, "grasp head"},
  };
  for (const Case& c : cases) {
    TinyInt8Model m = with_sensor_heads(c.heads);
    if (c.drop_grasp_head) {
      const auto base = m.tweak;
      m.tweak = [base](quantize::ModelBuilder& b) {
        base(b);
        b.metadata().has_grasp_head = false;
        b.metadata().golden.clear();
      };
    }
    const Error e = load_error(m.build());
    EXPECT_EQ(e.code(), ErrorCode::kModelInvalidMetadata) << c.what << ": " << e.message();
    EXPECT_NE(std::string(e.message()).find(c.says), std::string::npos)
        << c.what << ": " << e.message();
  }
}

}  // namespace
}  // namespace tlvlink::testing
