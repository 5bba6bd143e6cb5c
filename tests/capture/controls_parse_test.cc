// Control lists from configuration: parsing, errors naming the item, names and ids.
#include <linux/videodev2.h>

#include <gtest/gtest.h>

#include "tlvlink/capture/controls.h"

namespace tlvlink::capture {
namespace {

TEST(ParseControls, GelSightMiniSetup) {
  // What gsrobotics' mini_set_cam_params.sh sets with v4l2-ctl, as one configuration value.
  auto c = parse_controls(
      "auto_exposure=1, exposure_time_absolute=180; white_balance_automatic=0,"
      " white_balance_temperature=4500, gain=0");
  ASSERT_TRUE(c.ok()) << c.error().message();
  ASSERT_EQ(c->size(), 5u);
  EXPECT_EQ((*c)[1].name, "exposure_time_absolute");
  EXPECT_EQ((*c)[1].value, 180);
  EXPECT_EQ((*c)[1].id, 0u);  // resolved on the device
  EXPECT_EQ((*c)[3].value, 4500);
}

TEST(ParseControls, NumericIdsAndValues) {
  auto c = parse_controls("0x009a0902=-3, 9963776=0x10");
  ASSERT_TRUE(c.ok()) << c.error().message();
  EXPECT_EQ((*c)[0].id, 0x009a0902u);
  EXPECT_EQ((*c)[0].value, -3);
  EXPECT_EQ((*c)[1].id, 9963776u);
  EXPECT_EQ((*c)[1].value, 16);
}

TEST(ParseControls, EmptyTextIsNoControls) {
  auto c = parse_controls("  ,; ");
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->empty());
}

TEST(ParseControls, ErrorsNameTheItem) {
  struct Case {
    const char* text;
    const char* mentions;
  } cases[] = {
      {"gain", "'gain': expected name=value"},
      {"gain=high", "'gain=high': value is not an integer"},
      {"Gain=1", "'Gain=1': names are lower-case"},
      {"exposure time=3", "names are lower-case"},
      {"0x=1", "is not a control id"},
      {"gain=1=2", "value is not an integer"},
      {"gain=99999999999999999999", "value is not an integer"},
  };
  for (const Case& k : cases) {
    auto c = parse_controls(k.text);
    ASSERT_FALSE(c.ok()) << k.text;
    EXPECT_EQ(c.error().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(std::string(c.error().message()).find(k.mentions), std::string::npos)
        << k.text << " -> " << c.error().message();
  }
}

TEST(ParseControls, AtMostKMaxControls) {
  std::string many;
  for (size_t i = 0; i <= kMaxControls; ++i) many += "gain=1,";
  EXPECT_FALSE(parse_controls(many).ok());
}

TEST(ControlKey, MatchesV4l2Ctl) {
  char k[64];
  control_key("Exposure Time, Absolute", k, sizeof(k));
  EXPECT_STREQ(k, "exposure_time_absolute");
  control_key("White Balance, Automatic", k, sizeof(k));
  EXPECT_STREQ(k, "white_balance_automatic");
  control_key("Percentage of Dropped Buffers", k, sizeof(k));
  EXPECT_STREQ(k, "percentage_of_dropped_buffers");
  control_key("Inject V4L2_BUF_FLAG_ERROR", k, sizeof(k));
  EXPECT_STREQ(k, "inject_v4l2_buf_flag_error");
  control_key("  (trailing) ", k, sizeof(k));
  EXPECT_STREQ(k, "trailing");
  char small[6];
  control_key("Brightness", small, sizeof(small));
  EXPECT_STREQ(small, "brigh");
}

TEST(WellKnown, BothKernelSpellings) {
  EXPECT_EQ(well_known_control("exposure_time_absolute"),
            static_cast<uint32_t>(V4L2_CID_EXPOSURE_ABSOLUTE));
  EXPECT_EQ(well_known_control("exposure_absolute"),
            static_cast<uint32_t>(V4L2_CID_EXPOSURE_ABSOLUTE));
  EXPECT_EQ(well_known_control("auto_exposure"), static_cast<uint32_t>(V4L2_CID_EXPOSURE_AUTO));
  EXPECT_EQ(well_known_control("white_balance_temperature_auto"),
            static_cast<uint32_t>(V4L2_CID_AUTO_WHITE_BALANCE));
  EXPECT_EQ(well_known_control("led"), static_cast<uint32_t>(V4L2_CID_ZOOM_ABSOLUTE));
  EXPECT_EQ(well_known_control("percentage_of_dropped_buffers"), 0u);
}

}  // namespace
}  // namespace tlvlink::capture
