// Several calibration sources (`tlvlink quantize --calib A --calib B`): each gives its share of
// the counts, the frames are interleaved source by source (so bias correction's first N frames
// draw on every source alike), the formats are recorded in order, and a bad source or bad source
// count is an error naming it.

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "tlvlink/io/image.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/quantize/calib_data.h"
#include "tlvlink/quantize/reference_encoder.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

// A folder of `n` synthetic frames (PPM), each in its own subfolder (group).
std::string write_image_folder(const testing::TempDir& dir, int n) {
  const fs::path root = dir / "images";
  for (int i = 0; i < n; ++i) {
    const fs::path group = root / ("g" + std::to_string(i));
    fs::create_directories(group);
    tools::Image img{64, 48, 3, quantize::synthetic_touch_frame(48, 64, static_cast<uint64_t>(i))};
    EXPECT_TRUE(tools::write_pnm((group / "f.ppm").string(), img).ok());
  }
  return root.string();
}

// 32x32 RGB, x = pixel / 255.
InputSpec small_input() {
  static constexpr float kMean[3] = {0, 0, 0}, kStd[3] = {1, 1, 1};
  InputSpec spec;
  spec.height = 32;
  spec.width = 32;
  spec.channels = 3;
  spec.mean = kMean;
  spec.std = kStd;
  return spec;
}

bool is_extreme_key(const std::string& key) { return key.find('@') != std::string::npos; }

TEST(CalibSources, EachSourceGivesItsShareAndTheFramesAlternate) {
  testing::TempDir dir("calib_sources");
  quantize::CalibDataOptions o;
  o.paths = {"extreme", write_image_folder(dir, 12)};
  o.calib_count = 7;    // 4 + 3: the first source takes the remainder
  o.heldout_count = 3;  // 2 + 1
  o.progress = false;
  auto data = quantize::load_calib_data(o, small_input());
  ASSERT_TRUE(data.ok()) << data.error().message();
  EXPECT_EQ(data->formats, (std::vector<quantize::CalibFormat>{quantize::CalibFormat::kExtreme,
                                                               quantize::CalibFormat::kImages}));
  EXPECT_EQ(quantize::calib_formats_name(data->formats), "extreme+images");
  ASSERT_EQ(data->calibration.size(), 7u);
  ASSERT_EQ(data->calibration_keys.size(), 7u);
  ASSERT_EQ(data->heldout.size(), 3u);
  // A0 B0 A1 B1 A2 B2 A3: any prefix holds both sources.
  for (size_t i = 0; i < 7; ++i)
    EXPECT_EQ(is_extreme_key(data->calibration_keys[i]), i % 2 == 0)
        << i << ": " << data->calibration_keys[i];
  EXPECT_TRUE(is_extreme_key(data->heldout_keys[0]));
  EXPECT_FALSE(is_extreme_key(data->heldout_keys[1]));
  // One summary paragraph per source, in order.
  const size_t extreme = data->summary.find("extreme set"), images = data->summary.find("images ");
  ASSERT_NE(extreme, std::string::npos) << data->summary;
  ASSERT_NE(images, std::string::npos) << data->summary;
  EXPECT_LT(extreme, images);
  EXPECT_NE(data->summary.find('\n'), std::string::npos);
}

TEST(CalibSources, OneSourceIsUnchanged) {
  quantize::CalibDataOptions o;
  o.paths = {"extreme"};
  o.calib_count = 5;
  o.heldout_count = 2;
  o.progress = false;
  auto data = quantize::load_calib_data(o, small_input());
  ASSERT_TRUE(data.ok()) << data.error().message();
  EXPECT_EQ(data->calibration.size(), 5u);
  EXPECT_EQ(quantize::calib_formats_name(data->formats), "extreme");
  EXPECT_EQ(data->summary.find('\n'), std::string::npos);
}

TEST(CalibSources, BadSourceCountsAndABadSourceAreErrors) {
  quantize::CalibDataOptions o;
  o.progress = false;
  o.calib_count = 4;
  o.heldout_count = 0;
  auto none = quantize::load_calib_data(o, small_input());
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().code(), ErrorCode::kInvalidArgument);

  o.paths.assign(quantize::kMaxCalibrationSources + 1, "extreme");
  o.calib_count = 100;
  auto too_many = quantize::load_calib_data(o, small_input());
  ASSERT_FALSE(too_many.ok());
  EXPECT_EQ(too_many.error().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(too_many.error().message()).find("1..8"), std::string::npos)
      << too_many.error().message();

  o.paths = {"extreme", "extreme", "extreme"};
  o.calib_count = 2;  // fewer frames than sources: a source would give none
  auto starved = quantize::load_calib_data(o, small_input());
  ASSERT_FALSE(starved.ok());
  EXPECT_EQ(starved.error().code(), ErrorCode::kInvalidArgument);

  testing::TempDir dir("calib_sources_missing");
  o.paths = {"extreme", dir / "no-such-set"};
  o.calib_count = 4;
  auto missing = quantize::load_calib_data(o, small_input());
  ASSERT_FALSE(missing.ok());
  const std::string message = missing.error().message();
  EXPECT_NE(message.find("calibration source 2 of 2"), std::string::npos) << message;
  EXPECT_NE(message.find("no-such-set"), std::string::npos) << message;
}

}  // namespace
}  // namespace tlvlink
