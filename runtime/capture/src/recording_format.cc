#include "recording_format.h"

#include <cstring>

#include "tlvlink/crc32.h"

namespace tlvlink::capture::internal {

Status validate_recording_format(const RecordingFormat& f, const char* what) {
  const image::FrameFormat& ff = f.format;
  TLV_ENSURE(pixel_format_fourcc(ff.format) != 0, ErrorCode::kInvalidArgument,
             "%s: pixel format %d has no V4L2 fourcc", what, static_cast<int>(ff.format));
  TLV_ENSURE(ff.width >= 1 && ff.width <= kMaxRecordedSide && ff.height >= 1 &&
                 ff.height <= kMaxRecordedSide,
             ErrorCode::kInvalidArgument, "%s: frame size %dx%d is outside 1..%d", what, ff.width,
             ff.height, kMaxRecordedSide);
  TLV_ENSURE(ff.stride >= 0 && ff.stride <= 4 * kMaxRecordedSide, ErrorCode::kInvalidArgument,
             "%s: stride %d is outside 0..%d", what, ff.stride, 4 * kMaxRecordedSide);
  TLV_ENSURE(f.fps_denominator > 0, ErrorCode::kInvalidArgument,
             "%s: fps denominator is 0 (write 0/1 for an unknown rate)", what);
  return {};
}

void encode_file_header(const RecordingFormat& f, uint8_t (&out)[kRecordingHeaderBytes]) {
  std::memset(out, 0, sizeof(out));
  std::memcpy(out, kRecordingMagic, sizeof(kRecordingMagic));
  put_u16(out + kHdrVersion, kRecordingVersion);
  put_u16(out + kHdrSize, static_cast<uint16_t>(kRecordingHeaderBytes));
  put_u32(out + kHdrFourcc, pixel_format_fourcc(f.format.format));
  put_u32(out + kHdrWidth, static_cast<uint32_t>(f.format.width));
  put_u32(out + kHdrHeight, static_cast<uint32_t>(f.format.height));
  put_u32(out + kHdrStride, static_cast<uint32_t>(f.format.stride));
  put_u32(out + kHdrFpsNum, f.fps_numerator);
  put_u32(out + kHdrFpsDen, f.fps_denominator);
  put_u32(out + kHdrFlags, 0);
  put_u64(out + kHdrOrigin, static_cast<uint64_t>(f.origin_realtime_ns));
  put_u32(out + kHdrCrc, crc32(out, kHdrCrc));
}

Status decode_file_header(const uint8_t (&in)[kRecordingHeaderBytes], const char* path,
                          RecordingFormat& f, uint16_t& version) {
  TLV_ENSURE(std::memcmp(in, kRecordingMagic, sizeof(kRecordingMagic)) == 0, ErrorCode::kFormat,
             "recording %s: not a tlvlink recording (bad magic at offset 0)", path);
  version = get_u16(in + kHdrVersion);
  TLV_ENSURE(version == kRecordingVersion, ErrorCode::kFormat,
             "recording %s: version %u, this build reads version %u", path, version,
             kRecordingVersion);
  TLV_ENSURE(get_u16(in + kHdrSize) == kRecordingHeaderBytes, ErrorCode::kFormat,
             "recording %s: header size %u at offset %zu, expected %zu", path,
             get_u16(in + kHdrSize), kHdrSize, kRecordingHeaderBytes);
  const uint32_t crc = get_u32(in + kHdrCrc);
  TLV_ENSURE(crc == crc32(in, kHdrCrc), ErrorCode::kFormat,
             "recording %s: file header checksum mismatch (offset 0..%zu)", path,
             kRecordingHeaderBytes);
  const uint32_t fourcc = get_u32(in + kHdrFourcc);
  TLV_ENSURE(image::pixel_format_from_fourcc(fourcc, f.format.format), ErrorCode::kFormat,
             "recording %s: unknown pixel format fourcc 0x%08x at offset %zu", path, fourcc,
             kHdrFourcc);
  f.format.width = static_cast<int32_t>(get_u32(in + kHdrWidth));
  f.format.height = static_cast<int32_t>(get_u32(in + kHdrHeight));
  f.format.stride = static_cast<int32_t>(get_u32(in + kHdrStride));
  f.fps_numerator = get_u32(in + kHdrFpsNum);
  f.fps_denominator = get_u32(in + kHdrFpsDen);
  f.origin_realtime_ns = static_cast<int64_t>(get_u64(in + kHdrOrigin));
  TLV_ENSURE(get_u32(in + kHdrFlags) == 0, ErrorCode::kFormat,
             "recording %s: unknown header flags 0x%x", path, get_u32(in + kHdrFlags));
  Status st = validate_recording_format(f, path);
  if (!st.ok()) return Error(ErrorCode::kFormat, st.error().message());
  return {};
}

void encode_record_header(const RecordFields& r, uint8_t (&out)[kRecordHeaderBytes]) {
  std::memcpy(out, kRecordMagic, sizeof(kRecordMagic));
  put_u32(out + kRecFlags, r.flags);
  put_u64(out + kRecOffset, static_cast<uint64_t>(r.offset_ns));
  put_u32(out + kRecSequence, r.sequence);
  put_u32(out + kRecBytes, r.bytes);
  put_u32(out + kRecDataCrc, r.crc);
  put_u32(out + kRecHeaderCrc, crc32(out, kRecHeaderCrc));
}

const char* record_problem_text(RecordProblem p) {
  switch (p) {
    case RecordProblem::kNone: return "ok";
    case RecordProblem::kMagic: return "bad record magic (not at a record boundary)";
    case RecordProblem::kChecksum: return "record header checksum mismatch";
    case RecordProblem::kFlags: return "unknown record flags";
    case RecordProblem::kSize: return "frame size over the limit";
    case RecordProblem::kOffset: return "negative capture offset";
  }
  return "?";
}

RecordProblem decode_record_header(const uint8_t (&in)[kRecordHeaderBytes], RecordFields& r) {
  if (std::memcmp(in, kRecordMagic, sizeof(kRecordMagic)) != 0) return RecordProblem::kMagic;
  if (get_u32(in + kRecHeaderCrc) != crc32(in, kRecHeaderCrc)) return RecordProblem::kChecksum;
  r.flags = get_u32(in + kRecFlags);
  r.offset_ns = static_cast<int64_t>(get_u64(in + kRecOffset));
  r.sequence = get_u32(in + kRecSequence);
  r.bytes = get_u32(in + kRecBytes);
  r.crc = get_u32(in + kRecDataCrc);
  if ((r.flags & ~kRecordKnownFlags) != 0) return RecordProblem::kFlags;
  if (r.bytes > kMaxRecordedFrameBytes) return RecordProblem::kSize;
  if (r.offset_ns < 0) return RecordProblem::kOffset;
  return RecordProblem::kNone;
}

}  // namespace tlvlink::capture::internal
