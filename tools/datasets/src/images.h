#pragma once
#ifndef TLVLINK_DATASETS_PRIVATE
#error "images.h is internal to tools/datasets: include its public headers instead"
#endif
// Dataset images: checks, JPEG files, rotations. Internal to tlvlink_datasets.

#include <cstdint>
#include <string>

#include "tlvlink/datasets/records.h"
#include "tlvlink/datasets/report.h"
#include "tlvlink/error.h"

namespace tlvlink::datasets {

// kInvalidArgument naming `what` unless the image is non-empty RGB of height * width * 3 bytes.
Status check_image(const RgbImage& image, const std::string& what);

// Encodes and writes a JPEG; returns the bytes written.
Result<int64_t> write_jpeg_image(const std::string& path, const RgbImage& image, int32_t quality,
                                 bool full_chroma = false);
// JPEG encode + decode at `quality` (a camera's MJPEG stage), in place.
Status jpeg_round_trip(RgbImage& image, int32_t quality);

// Reads a JPEG into `out`. A missing or undecodable file is added to `report` (kind, path,
// reason) and false is returned.
bool load_jpeg_image(const std::string& path, int32_t scale_denominator, RgbImage& out,
                     LoadReport& report);

// Rotates by `quarter_turns` * 90 degrees counterclockwise (negative: clockwise).
RgbImage rotate_quarter_turns(const RgbImage& image, int32_t quarter_turns);

}  // namespace tlvlink::datasets
