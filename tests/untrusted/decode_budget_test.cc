// Image decoders check the declared size against the pixel cap and the file size before any
// buffer is allocated: the 136-byte JPEG declaring 16384x16384 and a PNG declaring more pixels
// than its bytes can hold are refused from their headers.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tlvlink/crc32.h"
#include "tlvlink/image/decode_budget.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/io/png.h"

namespace tlvlink {
namespace {

void put16(std::vector<uint8_t>& v, uint32_t x) {
  v.push_back(static_cast<uint8_t>(x >> 8));
  v.push_back(static_cast<uint8_t>(x));
}
void put32(std::vector<uint8_t>& v, uint32_t x) {
  put16(v, x >> 16);
  put16(v, x & 0xFFFF);
}

// SOI, DQT, SOF0 (one component), SOS, 40 data bytes, EOI: what the issue measured (~800 MB).
std::vector<uint8_t> jpeg_declaring(uint32_t width, uint32_t height) {
  std::vector<uint8_t> j = {0xFF, 0xD8, 0xFF, 0xDB, 0x00, 0x43, 0x00};
  j.insert(j.end(), 64, 1);
  j.insert(j.end(), {0xFF, 0xC0, 0x00, 0x0B, 0x08});
  put16(j, height);
  put16(j, width);
  j.insert(j.end(), {0x01, 0x01, 0x11, 0x00});
  j.insert(j.end(), {0xFF, 0xDA, 0x00, 0x08, 0x01, 0x01, 0x00, 0x00, 0x3F, 0x00});
  j.insert(j.end(), 40, 0);
  j.insert(j.end(), {0xFF, 0xD9});
  return j;
}

void chunk(std::vector<uint8_t>& png, const char* type, const std::vector<uint8_t>& data) {
  put32(png, static_cast<uint32_t>(data.size()));
  std::vector<uint8_t> td(type, type + 4);
  td.insert(td.end(), data.begin(), data.end());
  png.insert(png.end(), td.begin(), td.end());
  put32(png, crc32(td.data(), td.size()));
}

// A PNG whose IHDR declares width x height RGB, with `idat_bytes` of (unread) IDAT.
std::vector<uint8_t> png_declaring(uint32_t width, uint32_t height, size_t idat_bytes) {
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<uint8_t> ihdr;
  put32(ihdr, width);
  put32(ihdr, height);
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", std::vector<uint8_t>(idat_bytes, 0));
  chunk(png, "IEND", {});
  return png;
}

std::string png_error(const std::vector<uint8_t>& png) {
  auto img = tools::decode_png(std::as_bytes(std::span(png)), "bomb.png");
  return img.ok() ? "decoded" : img.error().message();
}

TEST(DecodeBudget, TinyJpegDeclaring16kIsRefusedFromItsHeader) {
  const std::vector<uint8_t> j = jpeg_declaring(16384, 16384);
  auto img = image::decode_jpeg(j, "bomb.jpg");
  ASSERT_FALSE(img.ok());
  EXPECT_EQ(img.error().code(), ErrorCode::kFormat);
  EXPECT_NE(std::string(img.error().message()).find("kMaxImagePixels"), std::string::npos)
      << img.error().message();
}

TEST(DecodeBudget, JpegDeclaringMoreThanItsBytesCanHoldIsRefused) {
  // 2000x2000 is under the pixel cap, but 12 MB from 136 bytes is beyond any Huffman coding.
  const std::vector<uint8_t> j = jpeg_declaring(2000, 2000);
  auto img = image::decode_jpeg(j, "bomb.jpg");
  ASSERT_FALSE(img.ok());
  EXPECT_NE(std::string(img.error().message()).find("decoded bytes per file byte"),
            std::string::npos)
      << img.error().message();
}

TEST(DecodeBudget, PngOverThePixelCapOrItsRatioIsRefused) {
  EXPECT_NE(png_error(png_declaring(16384, 16384, 64)).find("kMaxImagePixels"), std::string::npos);
  EXPECT_NE(png_error(png_declaring(4000, 4000, 64)).find("decoded bytes per file byte"),
            std::string::npos);
}

TEST(DecodeBudget, TheRulesThemselves) {
  EXPECT_TRUE(
      image::check_decode_budget(3280, 2464, 3, 400000, image::kJpegMaxRatio, "JPEG", "f").ok());
  EXPECT_FALSE(
      image::check_decode_budget(8192, 8192, 3, size_t{1} << 30, image::kJpegMaxRatio, "JPEG", "f")
          .ok());
  EXPECT_FALSE(image::check_decode_budget(64, 64, 3, 5, image::kJpegMaxRatio, "JPEG", "f").ok());
}

}  // namespace
}  // namespace tlvlink
