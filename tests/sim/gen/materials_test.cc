// The material table: the 20 TAG classes, ranges inside what the renderer accepts, and labels
// that follow the physics rules (and agree with TAG's class-level hard/soft).

#include <gtest/gtest.h>

#include <array>
#include <string_view>

#include "support/random.h"
#include "tlvlink/sim/materials.h"

namespace tlvlink::sim {
namespace {

constexpr int kSamplesPerClass = 500;

TEST(Materials, TwentyTagClassesInIdOrder) {
  constexpr std::array<std::string_view, kMaterialClassCount> kNames = {
      "concrete",         "plastic",        "glass",  "wood",  "metal", "brick", "tile", "leather",
      "synthetic fabric", "natural fabric", "rubber", "paper", "tree",  "grass", "soil", "rock",
      "gravel",           "sand",           "plants", "others"};
  const auto classes = material_classes();
  ASSERT_EQ(classes.size(), static_cast<size_t>(kMaterialClassCount));
  for (int32_t i = 0; i < kMaterialClassCount; ++i) {
    EXPECT_EQ(classes[static_cast<size_t>(i)].id, i);
    EXPECT_EQ(classes[static_cast<size_t>(i)].name, kNames[static_cast<size_t>(i)]);
    ASSERT_TRUE(material_class(i).ok());
    EXPECT_EQ(find_material_class(kNames[static_cast<size_t>(i)]),
              &classes[static_cast<size_t>(i)]);
  }
  // TAG: {leather, synthetic fabric, natural fabric, paper, grass} are soft.
  for (const MaterialClass& c : classes) {
    const bool soft = c.id == 7 || c.id == 8 || c.id == 9 || c.id == 11 || c.id == 13;
    EXPECT_EQ(c.tag_hard, !soft) << c.name;
  }
}

TEST(Materials, RangesAreInsideTheRenderersLimits) {
  for (const MaterialClass& c : material_classes()) {
    SCOPED_TRACE(std::string(c.name));
    auto inside = [](Range r, double lo, double hi) {
      return r.lo <= r.hi && r.lo >= lo && r.hi <= hi;
    };
    EXPECT_TRUE(inside(c.modulus_pa, 1e2, 1e13));
    EXPECT_GT(c.modulus_pa.lo, 0);
    EXPECT_TRUE(inside(c.poisson, 0, 0.5));
    EXPECT_TRUE(inside(c.friction, 0, 5));
    EXPECT_TRUE(inside(c.sq_um, 0, 500));
    EXPECT_GT(c.sq_um.lo, 0);
    EXPECT_TRUE(inside(c.correlation_length_mm, 0.01, 20));
    EXPECT_TRUE(inside(c.hurst, 0, 1));
    EXPECT_FALSE(c.pattern.empty());
    double shapes = 0;
    for (double w : c.press_shapes) shapes += w;
    EXPECT_GT(shapes, 0);
  }
}

TEST(Materials, SamplesStayInRangeAndLabelsFollowThePhysics) {
  const uint64_t seed = testing::test_seed();
  SCOPED_SEED_TRACE(seed);
  int rough = 0, smooth = 0, between = 0;
  for (const MaterialClass& c : material_classes()) {
    SCOPED_TRACE(std::string(c.name));
    for (int i = 0; i < kSamplesPerClass; ++i) {
      const Result<MaterialSample> r =
          sample_material(c.id, seed * 7919 + static_cast<uint64_t>(i));
      ASSERT_TRUE(r.ok()) << r.error().message();
      const MaterialSample& m = r.value();
      EXPECT_EQ(m.class_id, c.id);
      EXPECT_GE(m.modulus_pa, c.modulus_pa.lo);
      EXPECT_LE(m.modulus_pa, c.modulus_pa.hi);
      EXPECT_GE(m.friction, c.friction.lo);
      EXPECT_LE(m.friction, c.friction.hi);
      EXPECT_GE(m.sq_um, c.sq_um.lo);
      EXPECT_LE(m.sq_um, c.sq_um.hi);
      EXPECT_GE(m.correlation_length_mm, c.correlation_length_mm.lo);
      EXPECT_LE(m.correlation_length_mm, c.correlation_length_mm.hi);
      EXPECT_EQ(m.hard, m.modulus_pa > kHardModulusPa);
      EXPECT_EQ(m.hard, c.tag_hard) << "physics label disagrees with TAG's class label";
      const int32_t expected_rough = m.sq_um > kRoughSqUm ? 1 : (m.sq_um <= kSmoothSqUm ? 0 : -1);
      EXPECT_EQ(m.rough, expected_rough);
      rough += m.rough == 1;
      smooth += m.rough == 0;
      between += m.rough == -1;
    }
  }
  // Both labels are well represented across the table.
  const int total = kSamplesPerClass * kMaterialClassCount;
  EXPECT_GT(rough, total / 4);
  EXPECT_GT(smooth, total / 10);
  EXPECT_GT(between, 0);
}

TEST(Materials, SamplingIsDeterministicPerSeed) {
  const MaterialSample a = sample_material(3, 42).value();
  const MaterialSample b = sample_material(3, 42).value();
  const MaterialSample c = sample_material(3, 43).value();
  EXPECT_EQ(a.modulus_pa, b.modulus_pa);
  EXPECT_EQ(a.sq_um, b.sq_um);
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_NE(a.modulus_pa, c.modulus_pa);
}

TEST(Materials, BadClassIdIsAnError) {
  for (int32_t id : {-1, kMaterialClassCount, 1000}) {
    const Result<MaterialSample> r = sample_material(id, 1);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(r.error().message()).find("class id"), std::string::npos);
  }
  EXPECT_EQ(find_material_class("unobtainium"), nullptr);
}

TEST(Materials, ThermalFeelByEffusivity) {
  EXPECT_EQ(thermal_feel(*material_class(4).value()), ThermalFeel::kCool);  // metal
  EXPECT_EQ(thermal_feel(*material_class(2).value()), ThermalFeel::kCool);  // glass
  EXPECT_EQ(thermal_feel(*material_class(8).value()), ThermalFeel::kWarm);  // synthetic fabric
  EXPECT_EQ(thermal_feel(*material_class(9).value()), ThermalFeel::kWarm);  // natural fabric
}

}  // namespace
}  // namespace tlvlink::sim
