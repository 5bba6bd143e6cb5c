#pragma once
// Cheap per-frame checks every source applies before it delivers a frame (no decoding, O(1)
// except for skipping zero padding after an MJPEG end marker).

#include <cstdint>
#include <span>

#include "tlvlink/image/pixel_format.h"

namespace tlvlink::capture {

enum class FrameProblem : uint8_t {
  kNone = 0,
  kErrorFlag,  // the driver flagged the buffer (V4L2_BUF_FLAG_ERROR, libcamera FrameError)
  kEmpty,      // no payload
  kShort,      // uncompressed frame smaller than image::frame_bytes(format)
  kNoSoi,      // MJPEG that does not start with a start-of-image marker (FF D8)
  kNoEoi,      // MJPEG that does not end with an end-of-image marker (FF D9): truncated
};

// "none", "error_flag", "empty", "short", "mjpeg_no_soi", "mjpeg_no_eoi".
const char* frame_problem_name(FrameProblem problem);

// MJPEG framing: SOI first; EOI last, after which only zero bytes may follow (some UVC cameras
// pad their payload). A frame with both markers may still fail to decode; the decoder reports that.
FrameProblem check_mjpeg(std::span<const uint8_t> bytes);

// The checks for one frame of the given format, in order: flag, empty, MJPEG markers or size.
FrameProblem check_frame(std::span<const uint8_t> bytes, const image::FrameFormat& format,
                         bool error_flag);

}  // namespace tlvlink::capture
