#include "tlvlink/capture/frame_check.h"

namespace tlvlink::capture {

const char* frame_problem_name(FrameProblem problem) {
  switch (problem) {
    case FrameProblem::kNone: return "none";
    case FrameProblem::kErrorFlag: return "error_flag";
    case FrameProblem::kEmpty: return "empty";
    case FrameProblem::kShort: return "short";
    case FrameProblem::kNoSoi: return "mjpeg_no_soi";
    case FrameProblem::kNoEoi: return "mjpeg_no_eoi";
  }
  return "unknown";
}

FrameProblem check_mjpeg(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return FrameProblem::kEmpty;
  if (bytes.size() < 2 || bytes[0] != 0xFF || bytes[1] != 0xD8) return FrameProblem::kNoSoi;
  size_t end = bytes.size();
  while (end > 2 && bytes[end - 1] == 0) --end;  // zero padding some cameras append
  // The EOI must follow the SOI: a 2-byte "FF D8" alone, or FF D8 FF D9 with nothing between,
  // is not an image, but the decoder says so; here only the framing is checked.
  if (end < 4 || bytes[end - 2] != 0xFF || bytes[end - 1] != 0xD9) return FrameProblem::kNoEoi;
  return FrameProblem::kNone;
}

FrameProblem check_frame(std::span<const uint8_t> bytes, const image::FrameFormat& format,
                         bool error_flag) {
  if (error_flag) return FrameProblem::kErrorFlag;
  if (bytes.empty()) return FrameProblem::kEmpty;
  if (format.format == image::PixelFormat::kMjpeg) return check_mjpeg(bytes);
  return bytes.size() < image::frame_bytes(format) ? FrameProblem::kShort : FrameProblem::kNone;
}

}  // namespace tlvlink::capture
