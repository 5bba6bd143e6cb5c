#pragma once
// A stream recording's frame images (protocol 1.2 FrameImage, tlvlinkd `frame_images`) as a
// camera recording again: `tlvlink record --stream run.mcap --sensor 0 -o cam.tlvraw`, so what a
// board showed can be replayed through tlvlinkd. The JPEGs are kept byte for byte; their timing
// is not (the board sends at most 15 images a second): the recording plays them at --fps.
//
//   auto frames = stream_frame_images("run.mcap", 0);        // .mcap or .tlvrec
//   auto report = record::record_jpeg_frames(*frames, options, "cam.tlvraw");

#include <cstdint>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/record/record.h"

namespace tlvlink::foxglove {

// The FrameImages of `sensor` (its index in the Hello), in order. Errors: the file cannot be
// replayed (not a recording, an MCAP without tlvlink's record channel); when the recording holds
// no image of that sensor, the first call says which sensors it has images of (none: the board
// ran with frame_images off, its default).
Result<record::JpegFrameSource> stream_frame_images(const std::string& path, int32_t sensor);

}  // namespace tlvlink::foxglove
