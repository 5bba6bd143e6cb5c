// Sensor profiles and parameter validation: the built-in profiles are valid and match the notes;
// every NaN/Inf/out-of-range parameter is an error that names its field, at validate(), at
// Renderer::create() and at render().
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "sim/render/render_test_util.h"
#include "tlvlink/sim/extreme.h"

namespace tlvlink::sim {
namespace {

TEST(SimRenderProfiles, EveryNamedProfileIsValidAndRenders) {
  ASSERT_EQ(sensor_profile_names().size(), 4u);
  for (std::string_view name : sensor_profile_names()) {
    SCOPED_TRACE(std::string(name));
    auto p = sensor_profile(name);
    ASSERT_TRUE(p.ok()) << p.error().message();
    EXPECT_EQ(p->name, name);
    EXPECT_TRUE(validate(p.value()).ok());
    auto r = Renderer::create(p.value(), 3);
    ASSERT_TRUE(r.ok()) << r.error().message();
    EXPECT_EQ(r.value()->background().size(),
              static_cast<size_t>(p->height) * static_cast<size_t>(p->width) * 3);
    EXPECT_EQ(r.value()->profile().name, name);
  }
}

TEST(SimRenderProfiles, GeometryFollowsTheSensorNotes) {
  auto mini = sensor_profile("gelsight-mini");
  ASSERT_TRUE(mini.ok());
  EXPECT_EQ(mini->height, 240);
  EXPECT_EQ(mini->width, 320);
  EXPECT_DOUBLE_EQ(mini->mm_per_px, 0.0634);
  EXPECT_EQ(mini->raw_width, 3280);  // the camera only offers MJPEG 3280x2464
  EXPECT_EQ(mini->raw_height, 2464);
  EXPECT_EQ(mini->raw_format, "mjpeg");
  EXPECT_DOUBLE_EQ(mini->raw_crop, 0.15);  // 15 % of each border cut before resizing
  EXPECT_FALSE(mini->raw_transposed);
  auto digit = sensor_profile("digit");
  ASSERT_TRUE(digit.ok());
  EXPECT_EQ(digit->raw_width, 320);  // 320x240 camera mode, stored transposed (portrait)
  EXPECT_EQ(digit->raw_height, 240);
  EXPECT_TRUE(digit->raw_transposed);  // and flipped top to bottom, as digit_interface does
  EXPECT_DOUBLE_EQ(digit->raw_crop, 0.0);
  EXPECT_EQ(digit->width, 240);
  EXPECT_EQ(digit->height, 320);
  EXPECT_DOUBLE_EQ(digit->mm_per_px, 0.04);
  auto digit_vga = sensor_profile("digit-640x480");
  ASSERT_TRUE(digit_vga.ok());
  EXPECT_EQ(digit_vga->raw_width, 640);
  EXPECT_EQ(digit_vga->raw_height, 480);
  auto r15 = sensor_profile("gelsight-r1.5");
  ASSERT_TRUE(r15.ok());
  EXPECT_EQ(r15->height, 240);
  EXPECT_EQ(r15->width, 320);
  EXPECT_GE(r15->mm_per_px, 0.03);
  EXPECT_LE(r15->mm_per_px, 0.09);
  EXPECT_EQ(r15->light_count, 4);
}

TEST(SimRenderProfiles, UnknownNameIsAnErrorNamingIt) {
  auto p = sensor_profile("gelsight-max");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::strstr(p.error().message(), "gelsight-max"), nullptr) << p.error().message();
}

TEST(SimRenderValidation, DefaultsAreValid) {
  EXPECT_TRUE(validate(SensorProfile{}).ok());
  EXPECT_TRUE(validate(ContactScene{}).ok());
  EXPECT_TRUE(validate(RenderOptions{}).ok());
}

TEST(SimRenderValidation, EveryInvalidCaseIsAnErrorNamingItsField) {
  const auto cases = invalid_parameter_cases();
  // NaN, +Inf and -Inf for every floating-point field, plus range cases.
  ASSERT_GE(cases.size(), 100u);
  for (const InvalidCase& c : cases) {
    SCOPED_TRACE(c.name);
    const Status st = validate_all(c.sensor, c.scene, c.options);
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::strstr(st.error().message(), std::string(c.field).c_str()), nullptr)
        << st.error().message();
  }
}

TEST(SimRenderValidation, RendererRejectsInvalidInputsByName) {
  auto mini = testing::make_renderer("gelsight-mini");
  ASSERT_NE(mini, nullptr);
  Frame f;
  for (const InvalidCase& c : invalid_parameter_cases()) {
    SCOPED_TRACE(c.name);
    const std::string field(c.field);
    if (!validate(c.sensor).ok()) {
      auto r = Renderer::create(c.sensor, 1);
      ASSERT_FALSE(r.ok());
      EXPECT_NE(std::strstr(r.error().message(), field.c_str()), nullptr) << r.error().message();
    } else {
      const Status st = mini->render(c.scene, c.options, 1, f);
      ASSERT_FALSE(st.ok());
      EXPECT_NE(std::strstr(st.error().message(), field.c_str()), nullptr) << st.error().message();
    }
  }
}

TEST(SimRenderValidation, HeightMapMustMatchTheFrame) {
  auto mini = testing::make_renderer("gelsight-mini");
  ASSERT_NE(mini, nullptr);
  ContactScene s;
  s.geometry.shape = Shape::kHeightMap;
  s.geometry.height_map_mm.assign(100, 0.0f);
  Frame f;
  const Status st = mini->render(s, RenderOptions{}, 1, f);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(std::strstr(st.error().message(), "scene.geometry.height_map_mm"), nullptr)
      << st.error().message();
  s.geometry.height_map_mm.assign(240 * 320, 0.0f);
  s.geometry.height_map_mm[240 * 160 + 160] = 0.5f;  // a bump
  EXPECT_TRUE(mini->render(s, RenderOptions{}, 1, f).ok());
  EXPECT_TRUE(f.state.in_contact);
}

}  // namespace
}  // namespace tlvlink::sim
