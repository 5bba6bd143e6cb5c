// Frame checks: MJPEG framing (SOI/EOI, padding), empty and short uncompressed frames, flags.
#include "tlvlink/capture/frame_check.h"

#include <gtest/gtest.h>

#include <vector>

namespace tlvlink::capture {
namespace {

using image::FrameFormat;
using image::PixelFormat;

// SOI, an APP0 segment start, some payload, EOI: framing only, not a decodable image.
std::vector<uint8_t> framed_jpeg() {
  return {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x10, 'J', 'F', 'I', 'F', 0x00, 0x12, 0x34, 0xFF, 0xD9};
}

TEST(MjpegCheck, WellFramedPasses) { EXPECT_EQ(check_mjpeg(framed_jpeg()), FrameProblem::kNone); }

TEST(MjpegCheck, ZeroPaddingAfterEoiIsAccepted) {
  auto j = framed_jpeg();
  j.insert(j.end(), 4096, 0);  // some UVC cameras report the padded payload length
  EXPECT_EQ(check_mjpeg(j), FrameProblem::kNone);
}

TEST(MjpegCheck, ZeroLengthIsEmpty) { EXPECT_EQ(check_mjpeg({}), FrameProblem::kEmpty); }

TEST(MjpegCheck, TruncatedHasNoEoi) {
  const auto j = framed_jpeg();
  for (size_t n = 2; n < j.size(); ++n) {
    EXPECT_EQ(check_mjpeg(std::span(j).first(n)), FrameProblem::kNoEoi) << "truncated to " << n;
  }
}

TEST(MjpegCheck, MissingSoiIsReported) {
  auto j = framed_jpeg();
  j[1] = 0xD9;
  EXPECT_EQ(check_mjpeg(j), FrameProblem::kNoSoi);
  EXPECT_EQ(check_mjpeg(std::vector<uint8_t>{0xFF}), FrameProblem::kNoSoi);
  EXPECT_EQ(check_mjpeg(std::vector<uint8_t>(100, 0)), FrameProblem::kNoSoi);
}

TEST(MjpegCheck, GarbageAfterEoiIsNoEoi) {
  auto j = framed_jpeg();
  j.push_back(0x55);  // non-zero bytes after the end marker: a torn frame, not padding
  EXPECT_EQ(check_mjpeg(j), FrameProblem::kNoEoi);
}

TEST(MjpegCheck, SoiAloneOrSoiEoiOnlyAreRejected) {
  EXPECT_EQ(check_mjpeg(std::vector<uint8_t>{0xFF, 0xD8}), FrameProblem::kNoEoi);
  EXPECT_EQ(check_mjpeg(std::vector<uint8_t>{0xFF, 0xD8, 0x00, 0x00}), FrameProblem::kNoEoi);
  // "FF D8 FF D9" has both markers; whether it decodes is the decoder's call.
  EXPECT_EQ(check_mjpeg(std::vector<uint8_t>{0xFF, 0xD8, 0xFF, 0xD9}), FrameProblem::kNone);
}

TEST(FrameCheck, UncompressedSizes) {
  const FrameFormat yuyv{PixelFormat::kYuyv, 320, 240, 0};
  std::vector<uint8_t> full(320 * 240 * 2, 0x80);
  EXPECT_EQ(check_frame(full, yuyv, false), FrameProblem::kNone);
  EXPECT_EQ(check_frame(std::span(full).first(full.size() - 1), yuyv, false), FrameProblem::kShort);
  EXPECT_EQ(check_frame({}, yuyv, false), FrameProblem::kEmpty);
  EXPECT_EQ(check_frame(full, yuyv, true), FrameProblem::kErrorFlag);
  // Stride honoured: 320 pixels in 704-byte lines.
  const FrameFormat strided{PixelFormat::kYuyv, 320, 240, 704};
  EXPECT_EQ(check_frame(full, strided, false), FrameProblem::kShort);
  std::vector<uint8_t> padded(704 * 240);
  EXPECT_EQ(check_frame(padded, strided, false), FrameProblem::kNone);
  // All-zero and all-255 frames are valid images (extreme frames are not errors).
  const FrameFormat grey{PixelFormat::kGrey, 64, 48, 0};
  EXPECT_EQ(check_frame(std::vector<uint8_t>(64 * 48, 0), grey, false), FrameProblem::kNone);
  EXPECT_EQ(check_frame(std::vector<uint8_t>(64 * 48, 255), grey, false), FrameProblem::kNone);
  const FrameFormat nv12{PixelFormat::kNv12, 64, 48, 0};
  EXPECT_EQ(check_frame(std::vector<uint8_t>(64 * 48 * 3 / 2), nv12, false), FrameProblem::kNone);
  EXPECT_EQ(check_frame(std::vector<uint8_t>(64 * 48), nv12, false), FrameProblem::kShort);
}

TEST(FrameCheck, ErrorFlagWinsOverContent) {
  const FrameFormat mjpeg{PixelFormat::kMjpeg, 3280, 2464, 0};
  EXPECT_EQ(check_frame(framed_jpeg(), mjpeg, true), FrameProblem::kErrorFlag);
  EXPECT_EQ(check_frame(framed_jpeg(), mjpeg, false), FrameProblem::kNone);
}

TEST(FrameCheck, ProblemNames) {
  EXPECT_STREQ(frame_problem_name(FrameProblem::kNoEoi), "mjpeg_no_eoi");
  EXPECT_STREQ(frame_problem_name(FrameProblem::kShort), "short");
}

}  // namespace
}  // namespace tlvlink::capture
