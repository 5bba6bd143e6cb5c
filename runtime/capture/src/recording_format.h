#pragma once
// The byte layout of a recording (recording.h, README "Recorded raw streams"): encoding and
// decoding of the file header and the record headers, little-endian whatever the host.
// Private to runtime/capture.
#ifndef TLVLINK_CAPTURE_PRIVATE
#error "runtime/capture internal header: include tlvlink/capture/recording.h instead"
#endif

#include <cstdint>

#include "tlvlink/capture/recording.h"
#include "tlvlink/error.h"

namespace tlvlink::capture::internal {

inline constexpr uint8_t kRecordingMagic[8] = {0x89, 'T', 'L', 'V', 'R', 'E', 'C', '\n'};
inline constexpr uint8_t kRecordMagic[4] = {'F', 'R', 'M', '1'};

// File header offsets.
inline constexpr size_t kHdrVersion = 8, kHdrSize = 10, kHdrFourcc = 12, kHdrWidth = 16,
                        kHdrHeight = 20, kHdrStride = 24, kHdrFpsNum = 28, kHdrFpsDen = 32,
                        kHdrFlags = 36, kHdrOrigin = 40, kHdrCrc = 60;
// Record header offsets.
inline constexpr size_t kRecFlags = 4, kRecOffset = 8, kRecSequence = 16, kRecBytes = 20,
                        kRecDataCrc = 24, kRecHeaderCrc = 28;

inline void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline void put_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }
inline uint32_t get_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | p[i];
  return v;
}
inline uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | p[i];
  return v;
}

// Checks a format for writing (sizes, a pixel format with a fourcc, fps); names `what`.
Status validate_recording_format(const RecordingFormat& format, const char* what);

void encode_file_header(const RecordingFormat& format, uint8_t (&out)[kRecordingHeaderBytes]);
// Errors (kFormat) name `path` and what is wrong: magic, version, size, checksum, format.
Status decode_file_header(const uint8_t (&in)[kRecordingHeaderBytes], const char* path,
                          RecordingFormat& format, uint16_t& version);

struct RecordFields {
  uint32_t flags = 0;
  int64_t offset_ns = 0;
  uint32_t sequence = 0;
  uint32_t bytes = 0;
  uint32_t crc = 0;
};
void encode_record_header(const RecordFields& fields, uint8_t (&out)[kRecordHeaderBytes]);

enum class RecordProblem : uint8_t { kNone, kMagic, kChecksum, kFlags, kSize, kOffset };
const char* record_problem_text(RecordProblem problem);
// Decodes and checks magic, header checksum, flags, frame size and a non-negative offset.
RecordProblem decode_record_header(const uint8_t (&in)[kRecordHeaderBytes], RecordFields& out);

}  // namespace tlvlink::capture::internal
