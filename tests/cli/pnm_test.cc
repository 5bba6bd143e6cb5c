// PPM/PGM reading: valid variants (comments, whitespace) and strict rejection of the rest.

#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tlvlink/io/file.h"
#include "tlvlink/io/pnm.h"

namespace tlvlink::tools {
namespace {

std::vector<std::byte> bytes_of(const std::string& s) {
  std::vector<std::byte> b(s.size());
  std::memcpy(b.data(), s.data(), s.size());
  return b;
}

void expect_error(const std::string& file, const std::string& what) {
  const std::string name = "frames/bad.ppm";
  auto r = parse_pnm(bytes_of(file), name);
  ASSERT_FALSE(r.ok()) << "expected an error mentioning '" << what << "'";
  EXPECT_EQ(r.error().code(), ErrorCode::kFormat);
  const std::string msg = r.error().message();
  EXPECT_NE(msg.find(name), std::string::npos) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
}

TEST(Pnm, ReadsP6AndP5WithCommentsAndWhitespace) {
  const std::string rgb("\x01\x02\x03\x04\x05\x06\xfd\xfe\xff\x00\x00\x0a", 12);
  auto a = parse_pnm(bytes_of("P6\n# made by hand\n2 2\n255\n" + rgb), "a.ppm");
  ASSERT_TRUE(a.ok()) << a.error().message();
  EXPECT_EQ(a->width, 2);
  EXPECT_EQ(a->height, 2);
  EXPECT_EQ(a->channels, 3);
  EXPECT_EQ(a->at(1, 0, 2), 0xff);
  EXPECT_EQ(a->at(1, 1, 2), 0x0a);
  // Comments between every field, tabs and CRs as separators.
  auto b = parse_pnm(
      bytes_of(std::string("P5#c\n\t3 # width\r\n1\n#maxval next\n255 \x00\x80\xff", 39)), "b.pgm");
  ASSERT_TRUE(b.ok()) << b.error().message();
  EXPECT_EQ(b->channels, 1);
  EXPECT_EQ(b->at(0, 1, 0), 0x80);
  // A pixel byte that looks like whitespace or '#' right after maxval is data, not header.
  auto c = parse_pnm(bytes_of(std::string("P5 1 1 255\n#", 12)), "c.pgm");
  ASSERT_TRUE(c.ok()) << c.error().message();
  EXPECT_EQ(c->pixels[0], '#');
}

TEST(Pnm, RejectsMalformedFiles) {
  expect_error("P3\n1 1\n255\n0 0 0\n", "not a binary PPM/PGM");
  expect_error("GIF89a", "magic");
  expect_error("P", "too short");
  expect_error("P6\n2", "truncated header");
  expect_error("P6\n2 2\n", "no maxval");
  expect_error("P6\nx 2\n255\n", "width is not a number");
  expect_error("P6\n2 2\n65535\n" + std::string(24, '\0'), "maxval 65535");
  expect_error("P6\n2 2\n15\n" + std::string(12, '\0'), "maxval 15");
  expect_error("P6\n0 2\n255\n", "outside");
  expect_error("P6\n99999 2\n255\n", "outside");
  expect_error("P6\n99999999999 2\n255\n", "absurdly large");
  expect_error("P6\n2 2\n255\n" + std::string(11, '\0'), "truncated");
  expect_error("P6\n2 2\n255\n" + std::string(13, '\0'), "trailing bytes");
  expect_error("P6\n2 2 255", "truncated header");
  expect_error("P6\n2x 2 255\n", "followed by whitespace");
}

TEST(Pnm, RoundTripsAndNamesPathOnIoErrors) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("tlvlink_pnm_" + std::to_string(::getpid()) + ".ppm"))
                               .string();
  Image img{3, 2, 3, {}};
  for (int i = 0; i < 18; ++i) img.pixels.push_back(static_cast<uint8_t>(i * 14));
  ASSERT_TRUE(write_pnm(path, img).ok());
  auto back = read_pnm(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(back.ok()) << back.error().message();
  EXPECT_EQ(back->pixels, img.pixels);
  auto missing = read_pnm(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code(), ErrorCode::kIo);
  EXPECT_NE(std::string(missing.error().message()).find(path), std::string::npos);
}

}  // namespace
}  // namespace tlvlink::tools
